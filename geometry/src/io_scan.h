#pragma once
// Validation of mesh files before OpenMesh reads them.
//
// OpenMesh's readers trust their input: on a header whose counts lie, a truncated file, a
// non-numeric token or a PLY header without end_header they loop for billions of iterations,
// exhaust memory, or hand over silently wrong vertices (the stream fails and the last values are
// repeated). So every file is first walked here, token by token or record by record, by rules no
// looser than the reader's. A scan either throws InputError with the line (or record) at fault, or
// returns what the reader will hand over: counts and a fingerprint of every vertex and face,
// which load_mesh compares with what OpenMesh really read. It also returns the bytes to give
// OpenMesh: the file itself, or the file normalised where the reader would misread a valid file
// (a PLY comment just before end_header, OFF counts on the OFF line, OBJ material libraries).

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gimg::geo::io {

// Order-sensitive 64-bit hash of the values a reader hands over.
class Fingerprint {
public:
    void add(std::uint64_t value) {
        // splitmix64 finaliser, then a rotate-xor-multiply combine.
        std::uint64_t z = value + 0x9E3779B97F4A7C15ull;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        hash_ = ((hash_ << 5) | (hash_ >> 59)) ^ z;
        hash_ *= 0x100000001B3ull;
    }
    void add_position(float x, float y, float z) {
        add(std::bit_cast<std::uint32_t>(x));
        add(std::bit_cast<std::uint32_t>(y));
        add(std::bit_cast<std::uint32_t>(z));
    }
    bool operator==(const Fingerprint& other) const { return hash_ == other.hash_; }

private:
    std::uint64_t hash_ = 0xCBF29CE484222325ull;
};

// A face OpenMesh's reader alters or drops, as the file states it: the OBJ reader removes
// repeated vertices of a face and drops the face when fewer than three are left; the STL reader
// drops facets two of whose corners merge into one vertex.
struct KeptFace {
    std::size_t file_index = 0;
    bool reader_delivers = false;  // the reader hands over a reduced version of it
    std::vector<std::uint32_t> indices;
};

struct ScanResult {
    std::string format;                // "off", "ply", "obj", "stl"
    std::string encoding;              // "ascii", "binary_little_endian", "binary_big_endian", "binary"
    std::string reader_bytes;          // what OpenMesh reads
    std::size_t vertices = 0;          // vertices the reader adds
    std::size_t faces = 0;             // faces (polygons, facets) in the file
    std::size_t reader_faces = 0;      // faces the reader hands over
    Fingerprint vertex_fingerprint;    // of the positions the reader hands over, in order
    Fingerprint face_fingerprint;      // of the faces the reader hands over (corner count, indices)
    bool has_texcoords = false;        // per-vertex texture coordinates to ask the reader for
    std::vector<KeptFace> kept_faces;  // in file order
    std::vector<std::string> notes;    // normalisations worth telling the user about
};

// Each throws InputError (without the path; load_mesh adds it) for anything it cannot vouch for.
ScanResult scan_off(std::string_view bytes);
ScanResult scan_ply(std::string_view bytes);
ScanResult scan_obj(std::string_view bytes);
ScanResult scan_stl(std::string_view bytes);

}  // namespace gimg::geo::io

#pragma once
// Reading validated bytes through OpenMesh's readers (IOManager with a recording importer), so
// that every face the file holds is kept, also those a halfedge structure cannot hold.

#include "io_scan.h"

#include "gimg/geometry/error.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gimg::geo::io {

// The file passed gimg's validation but OpenMesh's reader handed over something else: a file
// variant the two read differently. An input error for the user, a bug report for the fuzzer.
class ReaderMismatch : public InputError {
public:
    using InputError::InputError;
};

// What a reader handed over, as it handed it over: float positions, polygons.
struct RawMesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> face_offsets{0};  // polygon f: face_indices[offsets[f], offsets[f+1])
    std::vector<std::uint32_t> face_indices;
    std::vector<glm::vec2> texcoords;        // per vertex when asked for, else empty
    std::vector<std::uint8_t> texcoord_set;  // 0: none given, 1: given, 2: given different ones
    std::size_t texcoord_conflicts = 0;      // vertices given two different ones (OBJ seams)

    std::size_t face_count() const { return face_offsets.size() - 1; }
};

// Hands scan.reader_bytes to OpenMesh's reader for scan.format (through a private temporary
// file, so that the bytes read are exactly the bytes validated), with OpenMesh's console output
// silenced. Throws ReaderMismatch when the reader fails or hands over other counts or values than
// the scan predicted. Serialised: OpenMesh's readers keep per-read state in singletons.
RawMesh read_with_openmesh(const ScanResult& scan);

}  // namespace gimg::geo::io

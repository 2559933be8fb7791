#pragma once
// The PLY header as io_scan_ply.cpp needs it: elements, properties, what each property is for,
// and the normalised header handed to OpenMesh's PLY reader.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gimg::geo::io {

enum class PlyScalar { i8, u8, i16, u16, i32, u32, f32, f64 };

std::size_t scalar_size(PlyScalar s);
bool is_float(PlyScalar s);

enum class PlyRole { skip, x, y, z, u, v, indices };

struct PlyProperty {
    std::string name;       // as in the file
    std::string type_name;  // as in the file (OpenMesh knows all 16 PLY type names)
    PlyScalar type = PlyScalar::f32;
    bool is_list = false;
    PlyScalar count_type = PlyScalar::u8;  // lists only
    PlyRole role = PlyRole::skip;
};

struct PlyElement {
    std::string name;
    std::uint32_t count = 0;
    std::vector<PlyProperty> properties;
    std::size_t line = 0;  // where the header declares it

    bool has_lists() const;
    std::size_t fixed_size() const;  // bytes of one item (lists count as their count field only)
};

enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::ascii;
    std::string encoding_name;
    std::vector<PlyElement> elements;
    std::size_t vertex_element = 0;  // indices into elements
    std::size_t face_element = 0;
    bool has_texcoords = false;
    std::size_t data_start = 0;  // byte offset just past the end_header line
    std::size_t data_line = 0;   // line number of the first data line (ascii)
    std::vector<std::string> notes;
};

// Parses and checks the header; throws InputError naming the line for anything OpenMesh's PLY
// reader would misread or gimg cannot use.
PlyHeader parse_ply_header(std::string_view bytes);

// The header OpenMesh reads: the vertex element, then the face element, nothing else; properties
// gimg does not use renamed so that the reader skips them by size; list counts spelt as the three
// count types the reader accepts (uchar, uint16, int).
std::string normalised_ply_header(const PlyHeader& header);

}  // namespace gimg::geo::io

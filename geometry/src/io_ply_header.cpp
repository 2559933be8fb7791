#include "io_ply_header.h"

#include "io_text.h"

#include "gimg/geometry/error.h"

#include <optional>

namespace gimg::geo::io {

namespace {

struct TypeName {
    std::string_view name;
    PlyScalar type;
};
constexpr TypeName kTypeNames[] = {
    {"char", PlyScalar::i8},   {"int8", PlyScalar::i8},     {"uchar", PlyScalar::u8},   {"uint8", PlyScalar::u8},
    {"short", PlyScalar::i16}, {"int16", PlyScalar::i16},   {"ushort", PlyScalar::u16}, {"uint16", PlyScalar::u16},
    {"int", PlyScalar::i32},   {"int32", PlyScalar::i32},   {"uint", PlyScalar::u32},   {"uint32", PlyScalar::u32},
    {"float", PlyScalar::f32}, {"float32", PlyScalar::f32}, {"double", PlyScalar::f64}, {"float64", PlyScalar::f64},
};

std::optional<PlyScalar> scalar_from_name(std::string_view name) {
    for (const TypeName& t : kTypeNames) {
        if (t.name == name) return t.type;
    }
    return std::nullopt;
}

[[noreturn]] void fail(std::size_t line, const std::string& message) {
    throw InputError("PLY header line " + std::to_string(line) + ": " + message);
}

PlyRole vertex_role(std::string_view name) {
    if (name == "x") return PlyRole::x;
    if (name == "y") return PlyRole::y;
    if (name == "z") return PlyRole::z;
    // OpenMesh reads u/s and v/t; MeshLab and others write texture_u/texture_v.
    if (name == "u" || name == "s" || name == "texture_u" || name == "texture_s") return PlyRole::u;
    if (name == "v" || name == "t" || name == "texture_v" || name == "texture_t") return PlyRole::v;
    return PlyRole::skip;
}

// Assigns roles in the vertex element and checks that x, y and z are there once and readable.
void assign_vertex_roles(PlyHeader& h) {
    PlyElement& e = h.elements[h.vertex_element];
    bool seen[7] = {};
    for (PlyProperty& p : e.properties) {
        if (p.is_list) fail(e.line, "list property " + quoted(p.name) + " in the vertex element is not supported");
        const PlyRole role = vertex_role(p.name);
        const auto r = static_cast<int>(role);
        if (role == PlyRole::skip) continue;
        if (seen[r]) {
            if (role == PlyRole::u || role == PlyRole::v) continue;  // a second texture name: skip it
            fail(e.line, "the vertex element declares " + quoted(p.name) + " twice");
        }
        seen[r] = true;
        p.role = role;
    }
    for (PlyRole need : {PlyRole::x, PlyRole::y, PlyRole::z}) {
        if (!seen[static_cast<int>(need)]) fail(e.line, "the vertex element has no x, y and z properties");
    }
    const bool binary = h.encoding != PlyEncoding::ascii;
    for (PlyProperty& p : e.properties) {
        // The binary reader converts only float and double to coordinates; it reads nothing at all
        // for other types, which would shift every value after them.
        if (binary && p.role != PlyRole::skip && !is_float(p.type)) {
            if (p.role == PlyRole::u || p.role == PlyRole::v) {
                h.notes.push_back("texture coordinate " + quoted(p.name) + " of type " + p.type_name +
                                  " is not read (OpenMesh reads float or double only)");
                p.role = PlyRole::skip;
                continue;
            }
            fail(e.line, "vertex coordinate " + quoted(p.name) + " of type " + p.type_name +
                             " is not supported in binary PLY (float or double only)");
        }
    }
    bool has_u = false, has_v = false;
    for (const PlyProperty& p : e.properties) {
        has_u = has_u || p.role == PlyRole::u;
        has_v = has_v || p.role == PlyRole::v;
    }
    if (has_u != has_v) {  // half a texture coordinate is no texture coordinate
        for (PlyProperty& p : e.properties) {
            if (p.role == PlyRole::u || p.role == PlyRole::v) p.role = PlyRole::skip;
        }
    }
    h.has_texcoords = has_u && has_v;
}

void assign_face_roles(PlyHeader& h) {
    PlyElement& e = h.elements[h.face_element];
    std::optional<std::size_t> indices;
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const std::string& name = e.properties[i].name;
        if (!indices && (name == "vertex_indices" || name == "vertex_index")) indices = i;
    }
    if (!indices) fail(e.line, "the face element has no 'property list ... vertex_indices'");
    // OpenMesh forgets the properties declared before vertex_indices and then misreads the data.
    if (*indices != 0) fail(e.line, "properties before vertex_indices in the face element are not supported");
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
        PlyProperty& p = e.properties[i];
        if (i == 0) {
            if (!p.is_list) fail(e.line, "vertex_indices must be a list property");
            if (is_float(p.type) || is_float(p.count_type)) {
                fail(e.line, "vertex_indices must be a list of integers with an integer count");
            }
            p.role = PlyRole::indices;
        } else if (p.is_list) {
            fail(e.line,
                 "list property " + quoted(p.name) + " in the face element is not supported (only vertex_indices)");
        }
    }
}

}  // namespace

std::size_t scalar_size(PlyScalar s) {
    switch (s) {
        case PlyScalar::i8:
        case PlyScalar::u8:
            return 1;
        case PlyScalar::i16:
        case PlyScalar::u16:
            return 2;
        case PlyScalar::i32:
        case PlyScalar::u32:
        case PlyScalar::f32:
            return 4;
        case PlyScalar::f64:
            return 8;
    }
    return 0;
}

bool is_float(PlyScalar s) { return s == PlyScalar::f32 || s == PlyScalar::f64; }

bool PlyElement::has_lists() const {
    for (const PlyProperty& p : properties) {
        if (p.is_list) return true;
    }
    return false;
}

std::size_t PlyElement::fixed_size() const {
    std::size_t bytes = 0;
    for (const PlyProperty& p : properties) bytes += scalar_size(p.is_list ? p.count_type : p.type);
    return bytes;
}

PlyHeader parse_ply_header(std::string_view bytes) {
    LineReader lines(bytes);
    std::string_view line;
    lines.next(line);
    if (const std::string_view magic = trim(line); magic != "ply" && magic != "PLY") {
        throw InputError("not a PLY file: the first line is " + quoted(magic) + " instead of 'ply'");
    }
    PlyHeader h;
    bool have_format = false, have_end = false;
    std::optional<std::size_t> vertex, face;
    while (lines.next(line)) {
        const std::size_t n = lines.line_number();
        require_text(line, "PLY header");
        Tokens t(line);
        std::string_view keyword;
        if (!t.next(keyword)) continue;
        std::vector<std::string_view> args;
        for (std::string_view a; t.next(a);) args.push_back(a);
        if (keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "end_header") {
            if (!args.empty()) fail(n, "end_header must stand alone on its line");
            have_end = true;
            break;
        }
        if (keyword == "format") {
            if (have_format) fail(n, "a second format line");
            if (args.size() != 2) fail(n, "format needs an encoding and a version");
            if (args[0] == "ascii")
                h.encoding = PlyEncoding::ascii;
            else if (args[0] == "binary_little_endian")
                h.encoding = PlyEncoding::binary_little_endian;
            else if (args[0] == "binary_big_endian")
                h.encoding = PlyEncoding::binary_big_endian;
            else
                fail(n, "unknown encoding " + quoted(args[0]));
            h.encoding_name = std::string(args[0]);
            have_format = true;
        } else if (keyword == "element") {
            if (!have_format) fail(n, "element before the format line");
            if (args.size() != 2) fail(n, "element needs a name and a count");
            PlyElement e;
            e.name = std::string(args[0]);
            e.line = n;
            if (!parse_uint32(args[1], e.count)) fail(n, "element count " + quoted(args[1]) + " is not a whole number");
            if (e.name == "vertex" || e.name == "face") {
                std::optional<std::size_t>& slot = e.name == "vertex" ? vertex : face;
                if (slot) fail(n, "a second '" + e.name + "' element");
                slot = h.elements.size();
            }
            h.elements.push_back(std::move(e));
        } else if (keyword == "property") {
            if (h.elements.empty()) fail(n, "property before any element");
            PlyProperty p;
            const bool list = !args.empty() && args[0] == "list";
            if (list ? args.size() != 4 : args.size() != 2) {
                fail(n, list ? "a list property needs a count type, an entry type and a name"
                             : "a property needs a type and a name");
            }
            p.is_list = list;
            const std::string_view type = args[list ? 2 : 0];
            p.name = std::string(args[list ? 3 : 1]);
            p.type_name = std::string(type);
            const auto scalar = scalar_from_name(type);
            if (!scalar) fail(n, "unknown property type " + quoted(type));
            p.type = *scalar;
            if (scalar_from_name(p.name)) fail(n, "a property named like a type (" + quoted(p.name) + ")");
            if (list) {
                const auto count = scalar_from_name(args[1]);
                if (!count) fail(n, "unknown list count type " + quoted(args[1]));
                p.count_type = *count;
            }
            h.elements.back().properties.push_back(std::move(p));
        } else {
            fail(n, "unknown header keyword " + quoted(keyword));
        }
    }
    if (!have_end) throw InputError("the PLY header has no end_header line (truncated or not a PLY file)");
    if (!have_format) throw InputError("the PLY header has no format line");
    if (!vertex) throw InputError("the PLY file has no vertex element");
    if (!face) throw InputError("the PLY file has no face element (gimg needs triangles, not a point cloud)");
    h.vertex_element = *vertex;
    h.face_element = *face;
    h.data_start = lines.position();
    h.data_line = lines.line_number() + 1;
    assign_vertex_roles(h);
    assign_face_roles(h);
    for (const PlyElement& e : h.elements) {
        if (e.name != "vertex" && e.name != "face") {
            h.notes.push_back("PLY element " + quoted(e.name) + " (" + std::to_string(e.count) + " items) skipped");
        }
    }
    if (h.elements[h.vertex_element].count == 0) throw InputError("the PLY header declares no vertices");
    if (h.elements[h.face_element].count == 0) throw InputError("the PLY header declares no faces");
    return h;
}

std::string normalised_ply_header(const PlyHeader& h) {
    auto count_type_name = [](PlyScalar s) -> std::string {
        switch (scalar_size(s)) {
            case 1:
                return "uchar";
            case 2:
                return "uint16";
            default:
                return "int";
        }
    };
    std::string out = "ply\nformat " + h.encoding_name + " 1.0\n";
    std::size_t skipped = 0;
    for (std::size_t which : {h.vertex_element, h.face_element}) {
        const PlyElement& e = h.elements[which];
        out += "element " + e.name + " " + std::to_string(e.count) + "\n";
        for (const PlyProperty& p : e.properties) {
            switch (p.role) {
                case PlyRole::x:
                    out += "property " + p.type_name + " x\n";
                    break;
                case PlyRole::y:
                    out += "property " + p.type_name + " y\n";
                    break;
                case PlyRole::z:
                    out += "property " + p.type_name + " z\n";
                    break;
                case PlyRole::u:
                    out += "property " + p.type_name + " u\n";
                    break;
                case PlyRole::v:
                    out += "property " + p.type_name + " v\n";
                    break;
                case PlyRole::indices:
                    out += "property list " + count_type_name(p.count_type) + " " + p.type_name + " vertex_indices\n";
                    break;
                case PlyRole::skip:
                    out += "property " + p.type_name + " gimg_skip_" + std::to_string(skipped++) + "\n";
                    break;
            }
        }
    }
    return out + "end_header\n";
}

}  // namespace gimg::geo::io

// save_mesh: PLY (binary little endian or ascii) and OBJ, written by gimg rather than OpenMesh:
// OpenMesh's writers work on its halfedge mesh, which cannot hold the non-manifold and duplicate
// faces a gimg Mesh may have. The whole file is built in memory and written atomically.

#include "gimg/geometry/io.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace gimg::geo {

namespace {

void check_savable(const Mesh& mesh, bool double_precision) {
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) {
        throw InputError("cannot save: " + std::to_string(mesh.normals.size()) + " normals for " +
                         std::to_string(mesh.positions.size()) + " vertices");
    }
    if (!mesh.texcoords.empty() && mesh.texcoords.size() != mesh.positions.size()) {
        throw InputError("cannot save: " + std::to_string(mesh.texcoords.size()) + " texture coordinates for " +
                         std::to_string(mesh.positions.size()) + " vertices");
    }
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::dvec3 p =
            double_precision ? mesh.positions[i] : glm::dvec3(glm::vec3(mesh.positions[i]));  // as written
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw InputError("cannot save: vertex " + std::to_string(i) +
                             " has a NaN, infinite or out-of-float-range coordinate");
        }
    }
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            if (mesh.triangles[f][k] >= mesh.positions.size()) {
                throw InputError("cannot save: triangle " + std::to_string(f) + " names vertex " +
                                 std::to_string(mesh.triangles[f][k]) + " of " + std::to_string(mesh.positions.size()));
            }
        }
    }
}

// Shortest decimal text that reads back as the same float.
void append_number(std::string& out, float v) {
    char buf[32];
    const auto result = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, result.ptr);
}

// Shortest decimal text that reads back as the same double.
void append_number(std::string& out, double v) {
    char buf[32];
    const auto result = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, result.ptr);
}

void append_number(std::string& out, std::uint64_t v) {
    char buf[24];
    const auto result = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, result.ptr);
}

template <typename T>
void append_binary(std::string& out, T value) {
    static_assert(std::endian::native == std::endian::little, "binary PLY is written little endian");
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
}

// One vertex's values: position, normal (if any), texture coordinates (if any), in the precision
// asked for.
template <typename Real>
int vertex_values(const Mesh& mesh, std::size_t i, Real values[8]) {
    int n = 0;
    for (int k = 0; k < 3; ++k) values[n++] = static_cast<Real>(mesh.positions[i][k]);
    if (mesh.has_normals())
        for (int k = 0; k < 3; ++k) values[n++] = static_cast<Real>(mesh.normals[i][k]);
    if (mesh.has_texcoords())
        for (int k = 0; k < 2; ++k) values[n++] = static_cast<Real>(mesh.texcoords[i][k]);
    return n;
}

template <typename Real>
void append_vertex(std::string& out, const Mesh& mesh, std::size_t i, bool binary) {
    Real values[8];
    const int n = vertex_values(mesh, i, values);
    for (int k = 0; k < n; ++k) {
        if (binary) {
            append_binary(out, values[k]);
        } else {
            if (k > 0) out += ' ';
            append_number(out, values[k]);
        }
    }
    if (!binary) out += '\n';
}

std::string ply_contents(const Mesh& mesh, bool binary, bool double_precision) {
    const bool uv = mesh.has_texcoords();
    const bool normals = mesh.has_normals();
    const std::string real = double_precision ? "double" : "float";
    std::string out = "ply\nformat ";
    out += binary ? "binary_little_endian" : "ascii";
    // The comment goes first: OpenMesh's reader misplaces binary data after a comment just
    // before end_header.
    out += " 1.0\ncomment written by gimg\nelement vertex " + std::to_string(mesh.vertex_count()) + "\nproperty " +
           real + " x\nproperty " + real + " y\nproperty " + real + " z\n";
    if (normals) out += "property " + real + " nx\nproperty " + real + " ny\nproperty " + real + " nz\n";
    if (uv) out += "property " + real + " s\nproperty " + real + " t\n";
    out +=
        "element face " + std::to_string(mesh.face_count()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    out.reserve(out.size() + mesh.vertex_count() * (binary ? 20 : 40) + mesh.face_count() * (binary ? 13 : 24));
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        if (double_precision) {
            append_vertex<double>(out, mesh, i, binary);
        } else {
            append_vertex<float>(out, mesh, i, binary);
        }
    }
    for (const glm::uvec3& t : mesh.triangles) {
        if (binary) {
            append_binary(out, std::uint8_t{3});
            for (int k = 0; k < 3; ++k) append_binary(out, static_cast<std::int32_t>(t[k]));
        } else {
            out += '3';
            for (int k = 0; k < 3; ++k) {
                out += ' ';
                append_number(out, std::uint64_t{t[k]});
            }
            out += '\n';
        }
    }
    return out;
}

// The coordinates of a position, normal or texture coordinate, as float32 or float64 text.
template <int N>
void append_coordinates(std::string& out, const glm::vec<N, double>& v, bool double_precision) {
    for (int k = 0; k < N; ++k) {
        out += ' ';
        if (double_precision) {
            append_number(out, v[k]);
        } else {
            append_number(out, static_cast<float>(v[k]));
        }
    }
    out += '\n';
}

std::string obj_contents(const Mesh& mesh, bool double_precision) {
    const bool uv = mesh.has_texcoords();
    const bool normals = mesh.has_normals();
    std::string out = "# written by gimg\n";
    out.reserve(mesh.vertex_count() * (uv ? 64 : 36) + mesh.face_count() * (uv ? 40 : 24));
    for (const glm::dvec3& position : mesh.positions) {
        out += 'v';
        append_coordinates(out, position, double_precision);
    }
    if (uv) {
        for (const glm::dvec2& t : mesh.texcoords) {
            out += "vt";
            append_coordinates(out, t, double_precision);
        }
    }
    if (normals) {
        for (const glm::dvec3& normal : mesh.normals) {
            out += "vn";
            append_coordinates(out, normal, double_precision);
        }
    }
    for (const glm::uvec3& t : mesh.triangles) {
        out += 'f';
        for (int k = 0; k < 3; ++k) {
            out += ' ';
            const std::uint64_t index = std::uint64_t{t[k]} + 1;  // OBJ counts from 1
            append_number(out, index);
            if (uv || normals) out += '/';
            if (uv) append_number(out, index);
            if (normals) {
                out += '/';
                append_number(out, index);
            }
        }
        out += '\n';
    }
    return out;
}

}  // namespace

void save_mesh(const Mesh& mesh, const std::filesystem::path& path, const SaveOptions& options) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".ply" && ext != ".obj") {
        throw InputError(path.string() + ": cannot save as '" + ext + "' (gimg writes .ply and .obj)");
    }
    try {
        check_savable(mesh, options.double_precision);
    } catch (const InputError& e) {
        throw InputError(path.string() + ": " + e.what());
    }
    write_file_atomically(path, ext == ".ply" ? ply_contents(mesh, options.binary, options.double_precision)
                                              : obj_contents(mesh, options.double_precision));
}

}  // namespace gimg::geo

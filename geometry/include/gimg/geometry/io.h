#pragma once
// Mesh files in and out. Reading goes through OpenMesh's readers (OBJ, PLY ascii/binary, OFF,
// STL); every face the file holds is kept in the returned Mesh (polygons are triangulated and
// counted), including faces a halfedge structure could not hold.

#include "gimg/geometry/mesh.h"

#include <cstddef>
#include <filesystem>
#include <string>

namespace gimg::geo {

struct LoadOptions {
    // Merge vertices with identical coordinates (off by default; reported when used).
    bool weld = false;
};

struct LoadReport {
    std::string format;                     // "obj", "ply", "off" or "stl"
    std::size_t file_vertices = 0;          // as the file states them, before welding
    std::size_t file_faces = 0;             // polygons in the file
    std::size_t polygons_triangulated = 0;  // polygons with more than three corners
    std::size_t welded_vertices = 0;        // vertices removed by welding
};

// Throws InputError with a one-line message for anything unusable: a missing, empty, truncated
// or garbage file, an unknown extension, NaN/Inf coordinates, faces naming missing vertices,
// faces of fewer than three vertices, zero faces, or a header whose counts the file cannot hold.
Mesh load_mesh(const std::filesystem::path& path, const LoadOptions& options = {},
               LoadReport* report = nullptr);

struct SaveOptions {
    bool binary = true;  // PLY only; OBJ is always text
};

// Writes .ply or .obj (by extension) to a temporary file beside `path`, then renames it, so an
// error never leaves a half-written file.
void save_mesh(const Mesh& mesh, const std::filesystem::path& path, const SaveOptions& options = {});

}  // namespace gimg::geo

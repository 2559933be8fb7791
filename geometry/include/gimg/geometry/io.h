#pragma once
// Mesh files in and out. Reading goes through OpenMesh's readers (OBJ, PLY ascii/binary, OFF,
// STL); every face the file holds is kept in the returned Mesh (polygons are triangulated and
// counted), including faces a halfedge structure could not hold.
//
// OpenMesh's readers trust their input, so each file is validated first (counts against the file
// size, every number and index, binary garbage); what OpenMesh then reads is compared with what
// the validation counted. See geometry/README.md for the rules of each format.

#include "gimg/geometry/mesh.h"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace gimg::geo {

struct LoadOptions {
    // Merge vertices with identical coordinates (off by default; reported when used).
    bool weld = false;
};

struct LoadReport {
    std::string format;                     // "obj", "ply", "off" or "stl"
    std::string encoding;                   // "ascii", "binary_little_endian", "binary_big_endian", "binary"
    std::size_t file_vertices = 0;          // as the file states them, before welding (STL: 3 per facet)
    std::size_t file_faces = 0;             // polygons (STL: facets) in the file
    std::size_t polygons_triangulated = 0;  // polygons with more than three corners
    bool welded = false;                    // vertices were merged: LoadOptions::weld, or an STL file
    std::size_t welded_vertices = 0;        // vertices removed by welding
    std::size_t texcoord_conflicts = 0;     // vertices the file gives two texture coordinates (OBJ seams)
    // What the loader changed, normalised or could not keep, one line each.
    std::vector<std::string> notes;
};

// Throws InputError with a one-line message naming the file for anything unusable: a missing,
// empty, truncated or garbage file, an unknown extension, NaN/Inf coordinates, faces naming missing
// vertices, faces of fewer than three vertices, zero faces, or a header whose counts the file
// cannot hold.
Mesh load_mesh(const std::filesystem::path& path, const LoadOptions& options = {}, LoadReport* report = nullptr);

struct SaveOptions {
    bool binary = true;  // PLY only; OBJ is always text
    // Positions, normals and texture coordinates as float64: for maps whose triangles are below
    // float32's resolution, e.g. conformal sphere maps of long limbs (areas of 1e-15 on the unit
    // sphere).
    bool double_precision = false;
};

// Writes .ply or .obj (by extension) to a temporary file beside `path`, then renames it, so an
// error never leaves a half-written file. Positions are written as float32 (exactly what
// load_mesh reads back) unless options.double_precision; texture coordinates when the mesh has
// them. Throws InputError for an
// unknown extension, indices out of range or non-finite coordinates (files gimg could not read).
void save_mesh(const Mesh& mesh, const std::filesystem::path& path, const SaveOptions& options = {});

}  // namespace gimg::geo

#pragma once
// The one triangle-mesh type used across gimg: an indexed triangle list in double precision.
// Algorithms in geometry/ work on these flat arrays (fast, easy to upload to the GPU); topology
// that needs halfedges (validation, decimation) builds an OpenMesh structure from it on demand.

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace gimg::geo {

struct Bounds {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
    double diagonal() const;
};

struct Mesh {
    std::vector<glm::dvec3> positions;
    // Vertex indices per triangle, counter-clockwise seen from the front (outside).
    std::vector<glm::uvec3> triangles;
    // Per-vertex texture coordinates: empty, or exactly one per position.
    std::vector<glm::dvec2> texcoords;
    // Per-vertex unit normals: empty, or exactly one per position (written by save_mesh; the
    // loaders do not read them).
    std::vector<glm::dvec3> normals;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t face_count() const { return triangles.size(); }
    bool has_texcoords() const { return !texcoords.empty() && texcoords.size() == positions.size(); }
    bool has_normals() const { return !normals.empty() && normals.size() == positions.size(); }
    // Bounding box of the positions; {0,0} for an empty mesh.
    Bounds bounds() const;
};

}  // namespace gimg::geo

#pragma once
// Topology of a triangle soup: counts, components, boundary loops, genus, and the defects
// (non-manifold edges and vertices, degenerate and duplicate faces, NaN coordinates, orientation)
// that decide which methods can take a mesh. Works on the flat triangle list, so it sees every
// face, also those a halfedge structure cannot hold.
//
// Definitions (also in geometry/README.md):
// - A face is *collapsed* when it repeats a vertex index. Collapsed faces count as faces, join
//   their vertices into one component and contribute their edges between distinct vertices, but
//   they are no surface: they are not counted on edges, in F of the Euler characteristic, in
//   fans or in orientation. A face is *degenerate* when collapsed or of zero area
//   (|cross| <= 1e-12 * longest edge^2).
// - An edge is an unordered pair of distinct vertices of some face. Its surface faces are the
//   non-collapsed faces having it: 1 makes a boundary edge, 2 a manifold edge, more than 2 a
//   non-manifold edge, 0 (only collapsed faces) a wire edge.
// - A vertex is non-manifold when its surface faces form more than one fan (faces joined through
//   the edges at that vertex). A vertex on a non-manifold edge is not counted for that alone.
// - Boundary loops: boundary edges chained at their end vertices; where several boundary chains
//   meet at a vertex, each continues within the fan it arrives in. Open chains count as loops.
// - Components: vertices joined by faces (faces only); vertices in no face are isolated vertices,
//   not components.
// - Euler characteristic per component: chi = V - E + F (vertices and edges of the component,
//   non-collapsed faces). Genus per component: g = (2 - chi - b) / 2, b its boundary loops, defined
//   only for components that are manifold (no non-manifold edge or vertex, no wire edge) and
//   orientable; otherwise unset.
// - Orientation: two faces agree on a manifold edge when they traverse it in opposite directions.
//   A component is oriented when all its manifold edges agree, orientable when flipping some of
//   its faces could make them agree. Non-manifold edges are ignored for orientation.
// - Duplicate faces: faces with the same vertex set as an earlier face (a pair counts once).

#include "gimg/geometry/mesh.h"

#include <cstddef>
#include <optional>
#include <vector>

namespace gimg::geo {

struct ComponentInfo {
    std::size_t vertices = 0;
    std::size_t faces = 0;
    std::size_t edges = 0;
    std::size_t boundary_loops = 0;
    long long euler_characteristic = 0;
    bool manifold = true;
    bool orientable = true;
    bool oriented = true;
    std::optional<long long> genus;
};

struct MeshInfo {
    std::size_t vertices = 0;
    std::size_t faces = 0;
    std::size_t edges = 0;
    std::size_t components = 0;
    std::size_t isolated_vertices = 0;
    std::vector<ComponentInfo> component_info;  // largest first (most faces), ties in face order
    std::size_t boundary_edges = 0;
    std::size_t boundary_loops = 0;
    std::size_t non_manifold_edges = 0;
    std::size_t non_manifold_vertices = 0;
    std::size_t wire_edges = 0;
    std::size_t degenerate_faces = 0;  // collapsed + zero-area
    std::size_t collapsed_faces = 0;
    std::size_t zero_area_faces = 0;
    std::size_t duplicate_faces = 0;
    std::size_t nonfinite_vertices = 0;  // vertices with a NaN or infinite coordinate
    std::size_t inconsistent_edges = 0;  // manifold edges whose two faces disagree on orientation
    bool closed = true;                  // no boundary edge
    bool manifold = true;                // every component manifold
    bool orientable = true;              // every component orientable
    bool oriented = true;                // every component oriented
    Bounds bbox;                         // of the finite vertex positions
};

// Throws InputError when a triangle names a vertex that does not exist.
MeshInfo analyze_topology(const Mesh& mesh);

// The zero-area test of the definitions above, for one face of distinct, existing vertices, and
// for a triangle given by its corners.
bool zero_area_face(const Mesh& mesh, const glm::uvec3& t);
bool zero_area_triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

}  // namespace gimg::geo

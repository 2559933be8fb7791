#pragma once
// A progressive mesh (Hoppe 1996) of a closed genus-0 triangle mesh: the coarse-to-fine hierarchy
// of hierarchical parameterizations (the spherical maps' hierarchy, MAPS's base domain).
//
// How it is built: Garland-Heckbert quadric error, halfedge collapses u -> k (u disappears, k keeps
// its ORIGINAL position), cheapest first. So every intermediate mesh is made of original vertices at
// their original places, and its triangles can be given in original vertex ids. A collapse is taken
// only if the result stays a closed 2-manifold of genus 0:
//   - link condition: u and k share exactly the two neighbours l and r opposite their edge, and the
//     mesh has more than 4 vertices (a tetrahedron cannot lose a vertex);
//   - down to the base mesh also geometry: no triangle around u may turn its normal by 90 degrees or
//     more (a flip) or become degenerate (zero area) when u moves to k.
// Below the base mesh the collapses go on to a tetrahedron with the link condition only (geometry
// can get poor there; only uniform-weight (Tutte) maps use those levels, and every sphere
// triangulation except the tetrahedron has an edge that passes the link condition).
//
// The record is the list of vertex splits that undo the collapses, coarsest first. Replaying them
// (see progressive_replay.h) or asking for levels (below) gives the intermediate meshes.

#include "gimg/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gimg::geo {

// Undoes one halfedge collapse: `vertex` comes back out of `parent`.
struct VertexSplit {
    std::uint32_t vertex = 0;  // the vertex this split adds (it was removed by the collapse)
    std::uint32_t parent = 0;  // the active vertex it splits from (kept by the collapse)
    // The two faces the split brings back, both holding `vertex` and `parent`: ids into the full
    // mesh's triangle list, and their corners at this moment (original ids, mesh orientation).
    // born_triangles[0] is (vertex, parent, left) up to rotation, born_triangles[1] (parent, vertex,
    // right); left and right are the two vertices opposite the edge {vertex, parent}.
    std::uint32_t born_faces[2] = {0, 0};
    glm::uvec3 born_triangles[2] = {glm::uvec3(0), glm::uvec3(0)};
    std::uint32_t left = 0, right = 0;
    // Faces that take `vertex` back in place of `parent`: moved_faces[moved_begin .. moved_end).
    std::uint32_t moved_begin = 0, moved_end = 0;
};

struct ProgressiveMesh {
    std::size_t vertex_count = 0;       // of the full mesh
    std::vector<glm::uvec3> triangles;  // the full mesh's triangles, as given
    // Vertices of the coarsest mesh (4 whenever the collapses reached a tetrahedron), ascending.
    std::vector<std::uint32_t> coarsest_vertices;
    // splits[i] turns the mesh of coarsest_vertices.size() + i vertices into the next one; all of
    // them in order give back the full mesh.
    std::vector<VertexSplit> splits;
    std::vector<std::uint32_t> moved_faces;  // ranges of VertexSplit::moved_begin/end
    // Vertex count of the base mesh: the coarsest mesh reached with the geometric checks, at most
    // the base_vertices asked for unless those checks stopped the collapses earlier.
    std::size_t base_vertex_count = 0;

    std::size_t coarsest_count() const { return coarsest_vertices.size(); }
};

// Builds the progressive mesh of a closed, manifold, genus-0 mesh (gimg::passes::check_sphere_input says whether it is).
// base_vertices below 4 counts as 4; a mesh with fewer vertices is its own base.
ProgressiveMesh build_progressive_mesh(const geo::Mesh& mesh, std::size_t base_vertices);

// For each vertex, its position in the activation order: the coarsest vertices first (0, 1, ...),
// then the vertex of split i at coarsest_count() + i. A mesh of n vertices holds exactly the
// vertices with activation index < n.
std::vector<std::uint32_t> activation_order(const ProgressiveMesh& pm);

// Triangles of the intermediate mesh with `active_count` vertices (coarsest_count() ..
// vertex_count), in original vertex ids, in the order of the full mesh's faces they stand for.
std::vector<glm::uvec3> triangles_at(const ProgressiveMesh& pm, std::size_t active_count);

// One level of a hierarchy for solvers that work level by level.
struct HierarchyLevel {
    std::vector<glm::uvec3> triangles;  // in ORIGINAL vertex ids, oriented like the input
    // Active vertices in activation order: the previous level's `vertices`, then `added`.
    std::vector<std::uint32_t> vertices;
    // Vertices added since the previous level (level 0: empty), in split order, so a vertex's
    // parent is active in the previous level or appears earlier in `added`.
    std::vector<std::uint32_t> added;
    std::vector<std::uint32_t> parent;  // for each added vertex, the active vertex it was split from
};

// Vertex counts of the levels: base, then growth x the previous one (rounded, at least one more),
// the last one the full mesh. growth must be > 1.
std::vector<std::size_t> level_vertex_counts(std::size_t base, std::size_t total, double growth);

// Levels from the base mesh (level 0) to the full mesh (last level), each `growth` times the
// vertices of the one before. Every level is a closed, manifold, genus-0 mesh; the last level's
// triangles are the input's triangles, in the input's order and corner order.
std::vector<HierarchyLevel> hierarchy_levels(const ProgressiveMesh& pm, double growth);

}  // namespace gimg::geo

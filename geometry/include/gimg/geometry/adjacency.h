#pragma once
// Compressed-sparse-row (CSR) adjacency of a triangle mesh, kept as flat uint32 arrays so GPU
// solvers can upload them as they are. Works on any triangle soup: non-manifold edges (any number
// of faces), isolated vertices and faces with repeated vertex indices do not break it.
//
// For a CSR pair (offsets, items), the items of element i are items[offsets[i] .. offsets[i+1]).

#include "gimg/geometry/mesh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace gimg::geo {

inline constexpr std::uint32_t kInvalidIndex = 0xffffffffu;

struct MeshAdjacency {
    // Vertex -> neighbouring vertices (joined by an edge), sorted ascending, no duplicates, never
    // the vertex itself. offsets has V + 1 entries.
    std::vector<std::uint32_t> vertex_vertex_offsets;
    std::vector<std::uint32_t> vertex_vertices;

    // Vertex -> incident faces, sorted ascending, each face once even if it names the vertex twice.
    std::vector<std::uint32_t> vertex_face_offsets;
    std::vector<std::uint32_t> vertex_faces;

    // Unique undirected edges as pairs (edges[2e], edges[2e+1]) with edges[2e] < edges[2e+1],
    // sorted lexicographically. Self-loops of degenerate faces (a, a) are not edges.
    std::vector<std::uint32_t> edges;

    // Edge -> incident faces, sorted ascending, each face once. One face: boundary edge; two:
    // manifold interior edge; more: non-manifold edge.
    std::vector<std::uint32_t> edge_face_offsets;
    std::vector<std::uint32_t> edge_faces;

    // Face -> its three edges: face_edges[3f + k] is the edge joining corners k and (k + 1) % 3
    // of triangle f, or kInvalidIndex when those corners are the same vertex.
    std::vector<std::uint32_t> face_edges;

    std::size_t vertex_count() const { return vertex_vertex_offsets.empty() ? 0 : vertex_vertex_offsets.size() - 1; }
    std::size_t edge_count() const { return edges.size() / 2; }
    std::size_t face_count() const { return face_edges.size() / 3; }

    std::span<const std::uint32_t> neighbors(std::size_t v) const {
        return {vertex_vertices.data() + vertex_vertex_offsets[v],
                vertex_vertex_offsets[v + 1] - vertex_vertex_offsets[v]};
    }
    std::span<const std::uint32_t> faces_of_vertex(std::size_t v) const {
        return {vertex_faces.data() + vertex_face_offsets[v], vertex_face_offsets[v + 1] - vertex_face_offsets[v]};
    }
    std::span<const std::uint32_t> faces_of_edge(std::size_t e) const {
        return {edge_faces.data() + edge_face_offsets[e], edge_face_offsets[e + 1] - edge_face_offsets[e]};
    }
    std::size_t edge_face_count(std::size_t e) const { return edge_face_offsets[e + 1] - edge_face_offsets[e]; }

    // Index of the edge {a, b} (either order), or kInvalidIndex when there is none. O(log E).
    std::uint32_t find_edge(std::uint32_t a, std::uint32_t b) const;

    // True for vertices whose every incident edge has exactly two faces and that have at least one
    // edge: the vertices where one-ring operators (curvature, Laplacians) are well defined.
    std::vector<std::uint8_t> interior_vertices() const;
};

// Builds all of the above in O(V + F) (bucketed by vertex, then tiny per-bucket sorts).
// Throws std::invalid_argument if a triangle names a vertex index >= mesh.vertex_count().
MeshAdjacency build_adjacency(const Mesh& mesh);

}  // namespace gimg::geo

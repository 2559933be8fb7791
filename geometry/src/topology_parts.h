#pragma once
// The pieces analyze_topology (topology.cpp) is built from: the edge table, the fans around each
// vertex, the boundary loops. Flat sorted arrays rather than a halfedge structure, because they
// must hold every face, also non-manifold and duplicate ones.

#include "gimg/geometry/mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gimg::geo::topo {

class UnionFind {
public:
    explicit UnionFind(std::size_t n);
    std::uint32_t find(std::uint32_t x);
    void unite(std::uint32_t a, std::uint32_t b);

private:
    std::vector<std::uint32_t> parent_;
};

// A face's side between two distinct vertices; sides of one edge are adjacent after sorting.
struct Side {
    std::uint32_t a = 0, b = 0;  // a < b
    std::uint32_t face = 0;
    bool forward = false;  // the face goes a -> b
    bool surface = false;  // the face is not collapsed
};

struct EdgeTable {
    std::vector<Side> sides;                // sorted by (a, b), then face
    std::vector<std::uint32_t> edge_begin;  // edge e: sides[edge_begin[e], edge_begin[e + 1])
    std::vector<std::uint32_t> surface;     // surface faces per edge

    std::size_t edge_count() const { return edge_begin.size() - 1; }
};

// `collapsed[f]`: face f repeats a vertex. Every index must name a vertex (analyze_topology checks
// them first).
EdgeTable build_edge_table(const Mesh& mesh, const std::vector<std::uint8_t>& collapsed);

// Per vertex, its surface faces and which fan each belongs to (faces joined through the edges
// at that vertex form one fan).
struct Fans {
    std::vector<std::uint32_t> begin;  // vertex v: faces[begin[v], begin[v + 1])
    std::vector<std::uint32_t> faces;
    std::vector<std::uint32_t> fan;    // fan number of faces[i] at its vertex, 0-based
    std::vector<std::uint32_t> count;  // fans per vertex

    std::uint32_t fan_of(std::uint32_t vertex, std::uint32_t face) const;
};

Fans build_fans(const Mesh& mesh, const std::vector<std::uint8_t>& collapsed);

// Boundary loops, each given by one of its vertices (for its component).
std::vector<std::uint32_t> boundary_loops(const EdgeTable& edges, const Fans& fans);

}  // namespace gimg::geo::topo

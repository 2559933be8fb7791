#pragma once
// Cutting a mesh open into a topological disk, as a square parameterization of a closed surface (or
// of one with several holes) needs: Gu, Gortler and Hoppe, "Geometry images", SIGGRAPH 2002, sec. 3.
//
// A cut is a set of the mesh's edges (one flag per MeshAdjacency edge). Opening the mesh along it
// gives every vertex one copy per wedge of its faces between cut edges, so the cut edges become
// boundary, each twice. The initial cut graph is what a spanning tree of the faces leaves uncrossed,
// with its dangling branches pruned: nothing on a disk, the loops of the handles on a closed surface
// of genus g (2g of them), paths joining the holes of a surface with several. A closed genus-0 surface
// prunes to nothing and needs a seam; paths from far points to the cut make the opened surface easier
// to flatten (passes::cut_to_disk chooses them).

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/mesh.h"

#include <cstdint>
#include <vector>

namespace gimg::geo {

// The initial cut graph (per edge, 1 on the cut). Boundary edges are never on it: they are open
// already. Expects one manifold component.
std::vector<std::uint8_t> initial_cut(const Mesh& mesh, const MeshAdjacency& adjacency);

// Vertices touching the cut or the boundary: where a path ends.
std::vector<std::uint8_t> cut_vertices(const MeshAdjacency& adjacency, const std::vector<std::uint8_t>& cut);

// Shortest edge-path distances (edge lengths) from every vertex marked in `sources`, with each
// vertex's predecessor on its path (kInvalidIndex at a source or where unreachable).
struct PathTree {
    std::vector<double> distance;  // infinity where unreachable
    std::vector<std::uint32_t> previous;
};
PathTree shortest_paths(const Mesh& mesh, const MeshAdjacency& adjacency, const std::vector<std::uint8_t>& sources);

// Puts the edges of `tree`'s path from `from` back to its source on the cut; returns their number.
std::size_t add_path(const MeshAdjacency& adjacency, const PathTree& tree, std::uint32_t from,
                     std::vector<std::uint8_t>& cut);

// A seam for a closed genus-0 surface: the shortest path between two far vertices (the farthest
// from vertex 0, then the farthest from that one), put on the cut; returns its number of edges.
std::size_t add_seam(const Mesh& mesh, const MeshAdjacency& adjacency, std::vector<std::uint8_t>& cut);

struct OpenedMesh {
    Mesh disk;                          // the same faces, their corners renumbered to the copies
    std::vector<std::uint32_t> source;  // disk vertex -> the mesh's vertex it copies (or kInvalidIndex)
};
// The mesh opened along the cut (see above); attributes per vertex (normals, texture coordinates)
// are copied with their vertex.
OpenedMesh open_along(const Mesh& mesh, const MeshAdjacency& adjacency, const std::vector<std::uint8_t>& cut);

// Splits at its midpoint every interior edge joining two boundary vertices, with the faces on it,
// so that no face has all three corners on the boundary. A map onto a convex polygon such as the
// square flattens a face whose corners land on one side, and no sample falls on it; a cut leaves
// many (elk's initial cut: 44 faces of no area in Floater's map). The surface stays the same; a
// new vertex has kInvalidIndex as its source. Returns the number of edges split.
std::size_t split_dividing_edges(OpenedMesh& opened);

}  // namespace gimg::geo

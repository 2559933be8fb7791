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
//
// Where two paths of a cut (or a path and a hole's rim) run side by side they close in a strip of
// faces whose corners all lie on the cut. A map onto the square crushes such a strip exponentially
// along its length wherever both of its sides land on one side of the square, below what doubles
// hold on turbine and holes: zip_closed_in moves the cut off such strips.

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/mesh.h"

#include <cstdint>
#include <vector>

namespace gimg::geo {

// The initial cut graph (per edge, 1 on the cut). Boundary edges are never on it: they are open
// already. Expects one manifold component.
//   FaceTree       the edges a tree of faces grown breadth first from face 0 leaves uncrossed (Gu et
//                  al.): long, zigzagging paths
//   ShortestLoops  the tree of faces crosses every edge but those of the tree of shortest paths from
//                  the surface's middle (holes drawn to points), taking first the edges that close
//                  the longest loops: what stays is the greedy shortest system of 2g loops through
//                  the middle (Erickson and Whittlesey, SODA 2005) and the shortest paths from it to
//                  the holes
// Neither is best on every mesh (passes::cut_to_disk tries both).
enum class CutGraph { FaceTree, ShortestLoops };
const char* cut_graph_name(CutGraph kind);  // "face tree", "shortest loops"
std::vector<std::uint8_t> initial_cut(const Mesh& mesh, const MeshAdjacency& adjacency,
                                      CutGraph kind = CutGraph::FaceTree);

// Vertices touching the cut or the boundary: where a path ends.
std::vector<std::uint8_t> cut_vertices(const MeshAdjacency& adjacency, const std::vector<std::uint8_t>& cut);

// Shortest edge-path distances (edge lengths) from every vertex marked in `sources`, with each
// vertex's predecessor on its path (kInvalidIndex at a source or where unreachable). With
// `free_rims`, a hole's rim costs nothing to walk: the first of its vertices reached reaches all of
// it, each along the rim.
struct PathTree {
    std::vector<double> distance;  // infinity where unreachable
    std::vector<std::uint32_t> previous;
};
PathTree shortest_paths(const Mesh& mesh, const MeshAdjacency& adjacency, const std::vector<std::uint8_t>& sources,
                        bool free_rims = false);

// Puts the edges of `tree`'s path from `from` back to its source on the cut; returns their number.
std::size_t add_path(const MeshAdjacency& adjacency, const PathTree& tree, std::uint32_t from,
                     std::vector<std::uint8_t>& cut);

// A seam for a closed genus-0 surface: the shortest path between two far vertices (the farthest
// from vertex 0, then the farthest from that one), put on the cut; returns its number of edges.
std::size_t add_seam(const Mesh& mesh, const MeshAdjacency& adjacency, std::vector<std::uint8_t>& cut);

// Moves the cut off the strips it closes in: a set of faces with every corner on the cut or a rim,
// joined across edges, that meets the rest of the opened surface at one edge (two paths leaving a
// vertex side by side, a path along a hole's rim). The strip is glued to the far side of its longest
// run along one cut path and parted at that edge instead, where this shortens the cut and leaves
// more than that one edge (which would open nothing): the opened surface stays a disk. Repeats
// until no strip can move; returns the moves made.
std::size_t zip_closed_in(const Mesh& mesh, const MeshAdjacency& adjacency, std::vector<std::uint8_t>& cut);

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

// Splits the longest boundary edges at their midpoints, with their faces, until the boundary has 4
// vertices, one for each corner of the square: a triangular hole, left by one missing face, is the
// whole boundary of a disk of genus 0. A new vertex has kInvalidIndex as its source. Returns the
// number of edges split (0 where the boundary has 4 vertices or more).
std::size_t split_short_boundary(OpenedMesh& opened);

}  // namespace gimg::geo

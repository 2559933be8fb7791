#pragma once
// Repair: turns a mesh with the defects analyze_topology reports (topology.h) into one the methods
// take, without moving a vertex: every edge with one or two faces, every vertex one fan, the faces
// of each piece turned alike, no face repeated or without area.
//
// In order:
//  1. optionally, vertices at identical positions merged (weld.h);
//  2. collapsed faces (a repeated vertex) and duplicate faces (the vertex set of an earlier face)
//     removed;
//  3. the faces of each piece turned to agree across their edges of two faces, by a walk from the
//     piece's first face; a piece then keeps the orientation of most of its area, so that a few
//     faces turned the wrong way are the ones turned back. An edge where the walk meets itself
//     turned the other way (a Moebius strip) is opened;
//  4. around an edge of more than two faces, faces paired by angle (each with the next one behind
//     it that runs along the edge the other way), the rest no longer joined there; every vertex
//     whose faces then form several fans copied once per fan after the first (with its texture
//     coordinate); faces that still close an edge with a third dropped;
//  5. faces of zero area (analyze_topology's test) removed: a cap, whose corner lies on its longest
//     edge, by flipping that edge (or, on the boundary, by dropping the face); a needle, with an
//     edge about 1e-6 of the longest or shorter, by collapsing that edge. Flips and collapses
//     that would break the mesh's manifoldness are skipped, and what is left is counted;
//  6. optionally, all but the piece of most faces removed; then every vertex in no face.
//
// Whatever the input, the result is manifold and oriented; it can still hold faces of zero area
// (zero_area_left), and it is empty when every face was defective.

#include "gimg/geometry/mesh.h"

#include <cstddef>

namespace gimg::geo {

struct RepairOptions {
    bool weld = false;     // step 1
    bool largest = false;  // step 6: keep only the piece of most faces
};

struct RepairReport {
    std::size_t welded_vertices = 0;  // merged away by step 1
    std::size_t collapsed_faces = 0;  // removed: a repeated vertex
    std::size_t duplicate_faces = 0;  // removed: the vertex set of an earlier face
    std::size_t turned_faces = 0;     // reversed to agree with their piece
    std::size_t opened_edges = 0;     // edges of more than two faces, or where the turning met itself
    std::size_t split_vertices = 0;   // copies made of vertices with several fans
    std::size_t dropped_faces = 0;    // faces that still closed an edge of a third face, removed
    std::size_t zero_area_faces = 0;  // faces of zero area before step 5
    std::size_t flipped_edges = 0;    // step 5's flips
    std::size_t collapsed_edges = 0;  // step 5's collapses
    std::size_t zero_area_left = 0;   // faces of zero area still there
    std::size_t dropped_pieces = 0;   // step 6
    std::size_t unused_vertices = 0;  // vertices in no face, removed
    // Whether anything changed.
    bool changed() const;
};

// Repairs `mesh` in place. Throws InputError for a triangle naming a vertex that does not exist or
// a vertex with a NaN or infinite coordinate.
RepairReport repair_mesh(Mesh& mesh, const RepairOptions& options = {});

}  // namespace gimg::geo

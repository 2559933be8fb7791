#pragma once
// The two sides of a slab piece (the mesh's and the polycube's) as local meshes: cut open to disks
// along paths between their loops, and their disk boundaries placed on the unit circle so the same
// contour parameter lands at the same angle on both sides (polycube_map.cpp composes them).

#include "polycube_parts.h"

#include <map>
#include <set>
#include <utility>

namespace gimg::passes::polycube {

inline constexpr std::uint32_t kNone = geo::kInvalidIndex;
inline constexpr double kTwoPi = 6.283185307179586;

// One side of a piece, with its own vertex numbering.
struct Local {
    std::vector<glm::dvec3> pos;
    std::vector<glm::uvec3> tri;
    std::vector<std::uint32_t> global;      // sliced-mesh vertex (mesh side), kNone for points added
    std::vector<std::uint32_t> origin;      // the vertex before cutting
    std::vector<std::int32_t> contour;      // on a loop: its contour, else -1
    std::vector<double> u;                  // on a loop: the contour parameter
    std::vector<std::uint32_t> tri_source;  // per triangle: sliced-mesh or surface triangle
    std::vector<glm::dvec2> disk;
};

// Normalised arc length from a common start, counter-clockwise seen from above, per point of a
// closed polyline: the start is where the line y = y_ref meets the loop at the largest x.
std::vector<double> loop_parameter(const std::vector<glm::dvec3>& p, double y_ref);

// The point of the closed polyline (with its parameters u) at parameter t.
glm::dvec3 point_at(const std::vector<glm::dvec3>& p, const std::vector<double>& u, double t);

// The vertex at parameter t on the boundary loop `loop` of m (a vertex already there, or a boundary
// edge split at the point of `curve` with that parameter, which is then inserted into `loop`, so that
// it stays what boundary_loops(m.tri) would give).
std::uint32_t vertex_at(Local& m, std::vector<std::uint32_t>& loop, double t, const std::vector<glm::dvec3>& curve,
                        const std::vector<double>& curve_u);

// Every triangle split in four at its edges' midpoints (the same surface, twice as fine): room for
// disjoint cuts where the paths of a coarse side wall each other off.
void subdivide(Local& m);

// Per vertex, its neighbours (sorted).
std::vector<std::vector<std::uint32_t>> neighbours(const Local& m);

// Shortest path from any of `from` to a vertex with target[v], through vertices with free[v] only;
// empty when there is none.
std::vector<std::uint32_t> shortest_path(const Local& m, const std::vector<std::vector<std::uint32_t>>& nb,
                                         const std::vector<std::uint32_t>& from,
                                         const std::vector<std::uint8_t>& target,
                                         const std::vector<std::uint8_t>& free);

// Every vertex on a cut edge gets one copy per wedge of triangles between cut or boundary edges.
void cut_open(Local& m, const std::set<std::pair<std::uint32_t, std::uint32_t>>& cut);

// One side's disk boundary as segments (a loop run, or a cut), in walk order.
struct Segment {
    int kind = 0;  // contour id + 1 for a loop run, -(cut + 1) for a cut
    std::vector<std::uint32_t> vertices;
    double length = 0.0;
};

// The single boundary loop of the cut piece, split where the edge kind changes, starting with the
// loop-0 run that leaves a copy of `start_landmark` (any run when there is no cut); ok false when
// the piece is not a disk or no such run exists.
std::vector<Segment> disk_segments(const Local& m, const std::map<std::pair<std::uint32_t, std::uint32_t>, int>& cut_of,
                                   std::uint32_t start_landmark, int loop0_kind, bool& ok);

// Disk positions on the unit circle: each segment an arc of `span`, loop runs placed by their
// contour parameter, cuts by arc length.
void place_boundary(Local& m, const std::vector<Segment>& segs, const std::vector<double>& span);

}  // namespace gimg::passes::polycube

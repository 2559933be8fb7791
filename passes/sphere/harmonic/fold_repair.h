#pragma once
// Local repair of a sphere map with a few flipped triangles. The planar polish (chart_problem.h)
// solves a cotangent Laplace equation, and where a mesh has obtuse triangles some cotangent
// weights are negative: the harmonic map is then not guaranteed one-to-one and folds a few
// triangles (triceratops 26, cow 89), while everywhere else it is far more conformal than the
// relaxed map it started from (triceratops 6 instead of 16 degrees mean). Rather than drop it, move
// the vertices around the folds into the kernels of their fans: a vertex inside its kernel sees
// every triangle of its fan counter-clockwise, so once every vertex of a fold has been moved there
// the fold is gone, and the moves touch nothing else.
//
// The kernel of vertex v's fan on the sphere is the set of points p with det(p, a, b) > 0 for every
// link edge (a, b), an intersection of hemispheres. Seen in the gnomonic projection about the
// fan's centre, which maps great circles to lines, it is a convex polygon: the intersection of the
// half-planes to the left of the projected link edges, found by clipping.
#include "sphere/harmonic/relaxation_mesh.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <vector>

namespace gimg::passes::detail {

struct FoldRepair {
    std::size_t flips_before = 0;
    std::size_t flips_after = 0;
    std::size_t moves = 0;  // vertex moves made
    std::size_t rings = 0;  // how far around the folds the repair reached
};

struct FoldRepairOptions {
    std::size_t max_rings = 16;
    std::size_t sweeps_per_round = 32;
    // Gives up after this many moves per vertex of the level: a map folded in thousands of places
    // (camel's polish) is not worth repairing.
    std::size_t moves_per_vertex = 16;
};

// Rounds r = 0, 1, ... max_rings: every vertex within r rings of a flipped triangle's corners
// whose fan is not all counter-clockwise (with the kernel test's margin, counter_clockwise()) or,
// from r = 1 on, every vertex of the region, moves to the centroid of its kernel, or where that is
// empty to its least folded point; up to sweeps_per_round Gauss-Seidel sweeps a round, until no
// triangle is flipped. Vertices further away keep their points exactly. `y` must be unit vectors.
FoldRepair repair_folds(const RelaxationMesh& level, std::vector<glm::dvec3>& y, const FoldRepairOptions& options = {});

// The kernel centroid of `v`'s fan on the sphere (unit vector), or false when the kernel is empty
// or the fan does not fit one open hemisphere.
bool fan_kernel_centroid(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t v,
                         glm::dvec3& centroid);

// Where the kernel is empty: the point that maximises the smallest signed distance (in the
// gnomonic projection) to the link edges' lines, within the link's bounding box widened by its
// size on every side; false when it is no better than where v is.
bool fan_least_folded_point(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t v,
                            glm::dvec3& point);

}  // namespace gimg::passes::detail

#pragma once
// The planar polish of a finished sphere map, step 1: the problem. Relaxation on the sphere moves
// each vertex towards its neighbours, so it needs about as many sweeps as a protrusion has rings
// squared to straighten the protrusion's shape, and a conformal map shrinks protrusions so much
// (bunny's ears to 1e-9 of the mean triangle) that they carry no energy the convergence test
// would miss: the relaxed map has mean angle errors of 20-80 degrees there. A conformal map stays
// conformal under stereographic projection, so in the plane it is harmonic: project the relaxed
// map from a pole inside its largest triangle, pin a small cap of vertices around the pole at
// their projected points (where the relaxed map is accurate) and solve the cotangent Laplace
// equation for all other vertices. That is one sparse linear system, solved by conjugate gradients
// (conjugate_gradients.h), which straightens a protrusion in about as many iterations as it has rings.
#include "solvers/spd_system.h"
#include "sphere/harmonic/relaxation_mesh.h"

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>

#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

// Pinning 1% of the vertices (at least 3): on bunny and armadillo 1% and 5% give the same angles,
// a single triangle (Choi's big triangle with the relaxed map's shape) distorts its neighbourhood
// (bunny 5.3 degrees mean instead of 0.8), and a 10-20% cap can take in a squeezed protrusion
// whose relaxed shape is still wrong (armadillo: flips).
inline constexpr double kChartCapFraction = 0.01;

// A x = b over the free vertices: A is the cotangent Laplacian restricted to them (diagonal: the
// sum of the vertex's spoke weights; off-diagonal: minus the weight of a spoke to another free
// vertex, columns are free (row) indices), b the pinned neighbours' pull. x holds the two chart
// coordinates of each free vertex; the start is the relaxed map in the chart.
struct ChartProblem : SpdSystem {
    glm::dmat3 frame{1.0};                     // columns e1, e2, e3: the pole is e3
    std::vector<std::uint32_t> free_vertices;  // row i is vertex free_vertices[i]
};

// The unit direction of the centroid of the largest triangle of `y` (chord area): where a relaxed
// map resolves the mesh best, so a cap pinned around it is accurate.
glm::dvec3 largest_triangle_pole(const RelaxationMesh& level, const std::vector<glm::dvec3>& y);

// Throws nothing; `y` must be flip-free unit vectors on `level`, at least near `pole`, around
// which the cap is pinned.
ChartProblem make_chart_problem(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, const glm::dvec3& pole,
                                double cap_fraction = kChartCapFraction);
// The same with the pole inside the largest triangle.
ChartProblem make_chart_problem(const RelaxationMesh& level, const std::vector<glm::dvec3>& y,
                                double cap_fraction = kChartCapFraction);

// The Dirichlet problem of vertices `pinned` at `chart[v]`; the free vertices start at theirs.
// The frame stays the identity: the chart is the caller's.
ChartProblem make_dirichlet_problem(const RelaxationMesh& level, const std::vector<std::uint8_t>& pinned,
                                    const std::vector<glm::dvec2>& chart);

// The sphere map with every free vertex at the inverse projection of its solution `x`; pinned
// vertices keep their point in `y`.
std::vector<glm::dvec3> sphere_points_from_chart(const ChartProblem& problem, const std::vector<glm::dvec3>& y,
                                                 const std::vector<glm::dvec2>& x);

}  // namespace gimg::passes::detail

// The direct route's start: Choi, Lam and Lui's pinned-triangle harmonic map, solved on the GPU by
// multigrid conjugate gradients, must be the map the linear method's sparse direct solver gives
// (its CPU reference), projected the same way; the covering test counts how often a map wraps
// the sphere.
#include "harmonic_test.h"
#include "test_data.h"

#include "sphere/harmonic/pinned_start.h"
#include "sphere/linear/plane_harmonic_map.h"
#include "sphere/linear/stereographic.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <numbers>

using namespace gimg;
using namespace gimg::passes::detail;

namespace {

class SphereHarmonicStart : public gimg::test::HarmonicGpuTest {};

// The CPU reference: sphere_linear's first two steps (Eigen's sparse LU of the same Dirichlet
// problem, the mean moved to the origin, the balancing scale, the inverse projection).
std::vector<glm::dvec3> reference_start(const geo::Mesh& mesh) {
    namespace ls = passes::linear_sphere;
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const std::uint32_t big = ls::most_regular_face(mesh);
    const ls::DirichletSolution plane = ls::harmonic_map_to_plane(mesh, adj, geo::cotangent_weights(mesh, adj), big);
    EXPECT_TRUE(plane.ok) << plane.why;
    const double scale = ls::balancing_scale(mesh, plane.z, big);
    std::vector<glm::dvec3> y(mesh.vertex_count());
    for (std::size_t v = 0; v < y.size(); ++v) y[v] = glm::normalize(ls::sphere_from_south_chart(scale * plane.z[v]));
    return y;
}

geo::Mesh lumpy_ellipsoid() {
    geo::Mesh m = geo::make_icosphere(1.0, 3);
    for (auto& p : m.positions) p = glm::dvec3(p.x, 2.0 * p.y, p.z) * (1.0 + 0.2 * p.x * p.y);
    return m;
}

}  // namespace

TEST_F(SphereHarmonicStart, MatchesTheLinearMethodsDirectSolve) {
    std::vector<std::pair<std::string, geo::Mesh>> cases{{"lumpy ellipsoid", lumpy_ellipsoid()}};
    if (auto path = test::shared_mesh("bunny_small.obj")) cases.emplace_back("bunny_small", geo::load_mesh(*path));
    for (const auto& [name, mesh] : cases) {
        SCOPED_TRACE(name);
        const RelaxationMesh level = build_relaxation_mesh(mesh);
        const PinnedStart start = pinned_start_gpu(ctx(), mesh, level, 1e-12, false);
        ASSERT_TRUE(start.why.empty()) << start.why;
        EXPECT_EQ(start.free_vertices, mesh.vertex_count() - 3);
        EXPECT_LE(start.residual, 1e-12);
        const std::vector<glm::dvec3> reference = reference_start(mesh);
        double worst = 0.0;
        for (std::size_t v = 0; v < reference.size(); ++v)
            worst = std::max(worst, glm::length(start.y[v] - reference[v]));
        EXPECT_LT(worst, 1e-8);
        // The accurate pole is where the plane's origin went: the south pole of the projection.
        EXPECT_LT(start.accurate_pole.z, -0.99);
    }
}

TEST_F(SphereHarmonicStart, ALooseToleranceStopsEarlier) {
    const geo::Mesh mesh = lumpy_ellipsoid();
    const RelaxationMesh level = build_relaxation_mesh(mesh);
    const PinnedStart loose = pinned_start_gpu(ctx(), mesh, level, 1e-4, false);
    const PinnedStart tight = pinned_start_gpu(ctx(), mesh, level, 1e-12, false);
    ASSERT_TRUE(loose.why.empty() && tight.why.empty());
    EXPECT_LE(loose.residual, 1e-4);
    EXPECT_LT(loose.iterations, tight.iterations);
}

TEST(SphereCovering, TotalSolidAngleCountsHowOftenAMapCoversTheSphere) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 3);
    const RelaxationMesh level = build_relaxation_mesh(sphere);
    const double four_pi = 4.0 * std::numbers::pi;
    EXPECT_NEAR(total_solid_angle(level, sphere.positions), four_pi, 1e-9);
    // Mirrored, every triangle is flipped: -1 times.
    std::vector<glm::dvec3> mirrored = sphere.positions;
    for (glm::dvec3& p : mirrored) p.x = -p.x;
    EXPECT_NEAR(total_solid_angle(level, mirrored), -four_pi, 1e-9);
    // Squeezed into a small cap, the back half folded onto the front: the halves cancel.
    std::vector<glm::dvec3> squeezed = sphere.positions;
    for (glm::dvec3& p : squeezed) p = glm::normalize(glm::dvec3(0.01 * p.x, 0.01 * p.y, 1.0));
    EXPECT_LT(std::abs(total_solid_angle(level, squeezed)), 0.1 * four_pi);
}

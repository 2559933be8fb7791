// The sphere solver's level layout and relaxation: fans and weights match the mesh, the colouring
// is proper, the GPU sweeps equal the CPU reference, and no sweep adds a flipped triangle.
#include "sphere/harmonic/relaxation_mesh.h"
#include "sphere/harmonic/relaxation.h"
#include "sphere/sphere_steps.h"

#include "gpu_test.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

using namespace gimg;
using passes::detail::RelaxationMesh;

namespace {

// An ellipsoid (so the cotangent weights are not those of a sphere) and a start on the sphere:
// its points projected radially, with a little noise that flips nothing.
struct Case {
    geo::Mesh mesh;
    std::vector<glm::dvec3> start;
};

Case ellipsoid_case(int subdivisions, double noise) {
    Case c;
    c.mesh = geo::make_icosphere(1.0, subdivisions);
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss(0.0, noise);
    for (glm::dvec3& p : c.mesh.positions) {
        c.start.push_back(glm::normalize(p + glm::dvec3(gauss(rng), gauss(rng), gauss(rng))));
        p *= glm::dvec3(1.0, 0.6, 0.35);
    }
    return c;
}

class SphereRelax : public gimg::test::GpuTest {};

}  // namespace

TEST(RelaxationMesh, FansFollowTheTrianglesAndWeightsAreTheCotangentWeights) {
    const Case c = ellipsoid_case(2, 0.0);
    const RelaxationMesh level = passes::detail::build_relaxation_mesh(c.mesh);
    std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> faces;
    for (const glm::uvec3& t : c.mesh.triangles) {
        faces.insert({t.x, t.y, t.z});
        faces.insert({t.y, t.z, t.x});
        faces.insert({t.z, t.x, t.y});
    }
    const geo::MeshAdjacency adj = geo::build_adjacency(c.mesh);
    const std::vector<double> w = geo::cotangent_weights(c.mesh, adj);
    ASSERT_EQ(level.vertex_count(), c.mesh.vertex_count());
    for (std::uint32_t v = 0; v < level.vertex_count(); ++v) {
        const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
        ASSERT_EQ(degree, adj.neighbors(v).size()) << "vertex " << v;
        for (std::uint32_t k = 0; k < degree; ++k) {
            const std::uint32_t a = level.ring[begin + k], b = level.ring[begin + (k + 1) % degree];
            EXPECT_TRUE(faces.count({v, a, b})) << "fan triangle (" << v << ", " << a << ", " << b << ") is not a face";
            EXPECT_NEAR(level.ring_weights[begin + k], w[adj.find_edge(v, a)], 1e-12);
        }
    }
}

TEST(RelaxationMesh, NoEdgeJoinsTwoVerticesOfOneColour) {
    const Case c = ellipsoid_case(3, 0.0);
    const RelaxationMesh level = passes::detail::build_relaxation_mesh(c.mesh);
    std::vector<std::uint32_t> colour(level.vertex_count(), ~0u);
    for (std::uint32_t k = 0; k < level.colour_count(); ++k)
        for (std::uint32_t m = level.colour_offsets[k]; m < level.colour_offsets[k + 1]; ++m)
            colour[level.colour_members[m]] = k;
    for (std::uint32_t v = 0; v < level.vertex_count(); ++v) {
        ASSERT_NE(colour[v], ~0u) << "vertex " << v << " has no colour";
        for (std::uint32_t k = level.ring_offsets[v]; k < level.ring_offsets[v + 1]; ++k)
            EXPECT_NE(colour[v], colour[level.ring[k]]) << "edge " << v << "-" << level.ring[k];
    }
    // Smallest-last order needs at most 6 colours on a planar graph (one dispatch per colour).
    EXPECT_LE(level.colour_count(), 6u);
}

TEST(RelaxationMesh, SweepsNeverAddAFlippedTriangleAndLowerTheEnergy) {
    Case c = ellipsoid_case(3, 0.0);
    // Push one vertex far across its neighbours: its fan flips.
    c.start[17] = glm::normalize(-c.start[17] + glm::dvec3(0.1, 0.0, 0.0));
    const RelaxationMesh level = passes::detail::build_relaxation_mesh(c.mesh);
    std::vector<glm::dvec3> y = c.start;
    auto previous = passes::detail::map_stats_cpu(level, y);
    ASSERT_GT(previous.flips, 0u);
    for (int sweep = 0; sweep < 30; ++sweep) {
        passes::detail::relax_sweep_cpu(level, y, sweep < 5);
        const auto now = passes::detail::map_stats_cpu(level, y);
        EXPECT_LE(now.flips, previous.flips) << "sweep " << sweep;
        previous = now;
    }
    EXPECT_EQ(previous.flips, 0u) << "the relaxation did not unfold the pushed vertex";
}

TEST(RelaxationMesh, ASliverWithinTheMarginNeverBecomesAFlip) {
    // A tetrahedron with one equilateral face: its sweeps drive the map towards a hemisphere, where
    // face (1, 2, 3) comes to lie within rounding of the origin (det 4e-16). Moves that lowered no
    // grade once flipped it there (sweeps 98 and 168), one vertex's move taking the noisy sign
    // for a flip and deepening it to -9e-10. A sliver is not a flip and must not become one.
    geo::Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const RelaxationMesh level = passes::detail::build_relaxation_mesh(m);
    const double s = 1.0 / std::sqrt(3.0);
    std::vector<glm::dvec3> y = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
    if (passes::detail::map_stats_cpu(level, y).flips) std::swap(y[0], y[1]);
    ASSERT_EQ(passes::detail::map_stats_cpu(level, y).flips, 0u);
    for (int sweep = 0; sweep < 300; ++sweep) {
        passes::detail::relax_sweep_cpu(level, y, false);
        ASSERT_EQ(passes::detail::map_stats_cpu(level, y).flips, 0u) << "sweep " << sweep;
        if (sweep % 32 == 31) passes::detail::relax_and_check_cpu(level, y, 0, false);  // as the solver recentres
    }
}

TEST_F(SphereRelax, GpuSweepsEqualTheCpuReference) {
    if (!ctx().device_info().shader_float64) GTEST_SKIP() << "device has no shaderFloat64";
    const Case c = ellipsoid_case(3, 0.03);
    const RelaxationMesh level = passes::detail::build_relaxation_mesh(c.mesh);
    std::vector<glm::dvec3> cpu = c.start;
    passes::detail::GpuRelaxation gpu(ctx(), level, c.start);
    double energy = passes::detail::map_stats_cpu(level, cpu).energy;
    double scale = passes::detail::kRecentreScale;
    for (auto [iterations, tutte] : {std::pair{3u, true}, std::pair{8u, false}, std::pair{8u, false}}) {
        SCOPED_TRACE(testing::Message() << iterations << " iterations, tutte " << tutte);
        const auto expected = passes::detail::relax_and_check_cpu(level, cpu, iterations, tutte, scale);
        scale = expected.recentre_kept ? passes::detail::kRecentreScale : 0.5 * scale;
        const auto got = gpu.run(iterations, tutte);
        EXPECT_NEAR(got.relaxed.energy, expected.relaxed.energy, 1e-9 * expected.relaxed.energy);
        EXPECT_EQ(got.relaxed.flips, expected.relaxed.flips);
        EXPECT_NEAR(glm::length(got.relaxed.centroid - expected.relaxed.centroid), 0.0, 1e-12);
        EXPECT_NEAR(got.recentred.energy, expected.recentred.energy, 1e-9 * expected.recentred.energy);
        EXPECT_EQ(got.recentre_kept, expected.recentre_kept);
        EXPECT_EQ(got.relaxed.flips, 0u);
        if (!tutte) {
            EXPECT_LT(got.relaxed.energy, energy) << "a conformal sweep must lower the energy";
        }
        energy = got.recentred.energy;
        const auto y = gpu.positions();
        double worst = 0.0;
        for (std::size_t v = 0; v < y.size(); ++v) worst = std::max(worst, glm::length(y[v] - cpu[v]));
        EXPECT_LT(worst, 1e-12);
        EXPECT_LT(glm::length(got.recentred.centroid), glm::length(got.relaxed.centroid) + 1e-15);
    }
}

TEST(RelaxationMesh, CentringUndoesAMoebiusPush) {
    // An icosphere's vertices have their mass centre at the origin; a Moebius push crowds them
    // to one side. Centring brings the centre back, and since the centred Moebius image of a point
    // set is unique up to a rotation, the icosphere's own edge lengths come back with it.
    const geo::Mesh mesh = geo::make_icosphere(1.0, 3);
    const RelaxationMesh level = passes::detail::build_relaxation_mesh(mesh);
    std::vector<glm::dvec3> y;
    for (const glm::dvec3& p : mesh.positions)
        y.push_back(passes::detail::moebius_move(glm::normalize(p), {0.2, -0.3, 0.6}));
    const passes::detail::MapStats before = passes::detail::map_stats_cpu(level, y);
    ASSERT_GT(glm::length(before.centroid), 0.5);
    const passes::detail::CentreRun run = passes::detail::centre_mass_cpu(level, y, before);
    EXPECT_TRUE(run.kept);
    EXPECT_GT(run.steps, 0u);
    EXPECT_LT(glm::length(run.stats.centroid), 1e-6);
    EXPECT_EQ(run.stats.flips, 0u);
    double worst = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            const double original = glm::length(glm::normalize(mesh.positions[a]) - glm::normalize(mesh.positions[b]));
            worst = std::max(worst, std::abs(glm::length(y[a] - y[b]) - original) / original);
        }
    EXPECT_LT(worst, 1e-4);
    // Already centred: nothing to do.
    const passes::detail::CentreRun again = passes::detail::centre_mass_cpu(level, y, run.stats);
    EXPECT_EQ(again.steps, 0u);
    EXPECT_TRUE(again.kept);
}

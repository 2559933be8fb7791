// Local repair of folded sphere maps (sphere/harmonic/fold_repair.h): folds made by hand on an
// icosphere's identity map are removed without touching vertices away from them, kernels are found
// or reported empty, and on the shared meshes whose planar polish folds a few triangles (obtuse
// triangles, negative cotangent weights) the repaired polish is kept and flip-free.
#include "sphere/harmonic/relaxation_mesh.h"
#include "sphere/sphere_steps.h"
#include "sphere/harmonic/fold_repair.h"

#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/sphere.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdio>
#include <set>

using namespace gimg;
using passes::detail::RelaxationMesh;

namespace {

struct Case {
    RelaxationMesh level;
    std::vector<glm::dvec3> y;  // the identity map: the icosphere's own points
};

Case icosphere_case(int subdivisions) {
    const geo::Mesh mesh = geo::make_icosphere(1.0, subdivisions);
    Case c{passes::detail::build_relaxation_mesh(mesh), {}};
    for (const glm::dvec3& p : mesh.positions) c.y.push_back(glm::normalize(p));
    return c;
}

std::set<std::uint32_t> within_rings(const RelaxationMesh& level, std::set<std::uint32_t> region, std::size_t rings) {
    for (std::size_t r = 0; r < rings; ++r) {
        std::set<std::uint32_t> next = region;
        for (std::uint32_t v : region)
            for (std::uint32_t k = level.ring_offsets[v]; k < level.ring_offsets[v + 1]; ++k)
                next.insert(level.ring[k]);
        region = std::move(next);
    }
    return region;
}

class SphereUntangle : public gimg::test::GpuTest {};

}  // namespace

TEST(SphereUntangleCpu, RemovesAFoldAndLeavesTheRestAlone) {
    Case c = icosphere_case(4);
    const std::vector<glm::dvec3> original = c.y;
    // Vertex 100 mirrored across its first neighbour: its fan turns inside out around there.
    const std::uint32_t v = 100, a = c.level.ring[c.level.ring_offsets[v]];
    c.y[v] = glm::normalize(2.0 * c.y[a] - c.y[v]);
    ASSERT_GT(passes::detail::map_stats_cpu(c.level, c.y).flips, 0u);

    const passes::detail::FoldRepairOptions options;
    const auto r = passes::detail::repair_folds(c.level, c.y, options);
    EXPECT_GT(r.flips_before, 0u);
    EXPECT_EQ(r.flips_after, 0u);
    EXPECT_EQ(passes::detail::map_stats_cpu(c.level, c.y).flips, 0u);
    // Only vertices within the rounds' reach of the fold may move (its corners lie within one
    // ring of v), and only as far as the rounds needed.
    const std::set<std::uint32_t> reach = within_rings(c.level, {v}, r.rings + 1);
    for (std::uint32_t u = 0; u < c.level.vertex_count(); ++u) {
        if (reach.count(u)) continue;
        ASSERT_EQ(c.y[u], original[u]) << "vertex " << u;
    }
    for (const glm::dvec3& p : c.y) ASSERT_NEAR(glm::length(p), 1.0, 1e-12);
}

TEST(SphereUntangleCpu, RemovesAMirroredDisk) {
    Case c = icosphere_case(4);
    // The disk of three rings around a vertex mirrored across a plane through it: every triangle
    // inside is inside out and the fans inside have folded links (empty kernels), so the repair
    // has to go through least folded points.
    const std::uint32_t v = 300, a = c.level.ring[c.level.ring_offsets[v]];
    const glm::dvec3 n = glm::normalize(glm::cross(c.y[v], c.y[a]));
    const std::set<std::uint32_t> disk = within_rings(c.level, {v}, 3);
    for (std::uint32_t u : disk) c.y[u] -= 2.0 * glm::dot(c.y[u], n) * n;
    const std::vector<glm::dvec3> mirrored = c.y;
    const std::size_t before = passes::detail::map_stats_cpu(c.level, c.y).flips;
    ASSERT_GT(before, 40u);
    const auto r = passes::detail::repair_folds(c.level, c.y);
    std::printf("mirrored disk: %zu flips, %zu moves over %zu rings\n", before, r.moves, r.rings);
    EXPECT_EQ(r.flips_before, before);
    EXPECT_EQ(r.flips_after, 0u);
    EXPECT_EQ(passes::detail::map_stats_cpu(c.level, c.y).flips, 0u);
    const std::set<std::uint32_t> reach = within_rings(c.level, disk, r.rings + 1);
    for (std::uint32_t u = 0; u < c.level.vertex_count(); ++u) {
        if (reach.count(u)) continue;
        ASSERT_EQ(c.y[u], mirrored[u]) << "vertex " << u;
    }
}

TEST(SphereUntangleCpu, KernelCentroidIsInTheKernelOrReportedEmpty) {
    Case c = icosphere_case(3);
    for (std::uint32_t v = 0; v < c.level.vertex_count(); v += 7) {
        glm::dvec3 p;
        ASSERT_TRUE(passes::detail::fan_kernel_centroid(c.level, c.y, v, p)) << v;
        const std::uint32_t begin = c.level.ring_offsets[v], degree = c.level.ring_offsets[v + 1] - begin;
        for (std::uint32_t k = 0; k < degree; ++k)
            EXPECT_TRUE(passes::detail::counter_clockwise(p, c.y[c.level.ring[begin + k]],
                                                          c.y[c.level.ring[begin + (k + 1) % degree]]));
        // The icosphere's fans are nearly regular: the centroid is close to the vertex itself.
        EXPECT_LT(glm::length(p - c.y[v]), 0.1 * glm::length(c.y[c.level.ring[begin]] - c.y[v]));
    }
    // One link vertex pulled across the opposite side of the link: the link polygon folds over
    // itself and no point sees all its edges counter-clockwise.
    const std::uint32_t v = 10, begin = c.level.ring_offsets[v], degree = c.level.ring_offsets[v + 1] - begin;
    const std::uint32_t near = c.level.ring[begin], far = c.level.ring[begin + degree / 2];
    c.y[near] = glm::normalize(c.y[far] + 2.0 * (c.y[far] - c.y[v]));
    glm::dvec3 p;
    EXPECT_FALSE(passes::detail::fan_kernel_centroid(c.level, c.y, v, p));
    // Where the vertex is, its worst triangle is flipped; the least folded point is better.
    glm::dvec3 q;
    ASSERT_TRUE(passes::detail::fan_least_folded_point(c.level, c.y, v, q));
}

TEST_F(SphereUntangle, PolishIsRepairedOnMeshesWhereItFolds) {
    // triceratops and cow: obtuse triangles give negative cotangent weights, and the planar
    // polish folds 26 and 89 triangles. Repaired, it is kept: flip-free, with at most half the
    // angle distortion of the relaxed map without it, and a lower energy.
    if (!ctx().device_info().shader_float64) GTEST_SKIP() << "device has no shaderFloat64";
    for (const char* name : {"triceratops.off", "cow.off"}) {
        auto path = test::shared_mesh(name);
        if (!path) GTEST_SKIP() << "shared mesh " << name << " not found (set GIMG_MESH_DIR)";
        SCOPED_TRACE(name);
        const geo::Mesh mesh = geo::load_mesh(*path);
        passes::HarmonicSphereOptions hierarchy;  // the polish of the hierarchy's relaxed map folds
        hierarchy.direct = false;
        const passes::SphereResult polished = passes::sphere_harmonic(ctx(), mesh, hierarchy);
        passes::HarmonicSphereOptions no_polish;
        no_polish.plane_polish = false;
        const passes::SphereResult relaxed = passes::sphere_harmonic(ctx(), mesh, no_polish);
        const passes::SphereMetrics p = passes::sphere_metrics(mesh, polished.positions);
        const passes::SphereMetrics q = passes::sphere_metrics(mesh, relaxed.positions);
        std::printf("%-16s angle mean: relaxed %.2f, polished and untangled %.2f; ratio %.5f -> %.5f\n", name,
                    q.angle_distortion_deg.mean, p.angle_distortion_deg.mean, q.conformal_ratio, p.conformal_ratio);
        EXPECT_EQ(polished.note.find("chart solve rejected"), std::string::npos) << polished.note;
        EXPECT_TRUE(std::any_of(polished.stages.begin(), polished.stages.end(), [](const passes::SphereStage& s) {
            return s.name.starts_with("chart solve: fold repair");
        }));
        EXPECT_EQ(p.flips, 0u);
        EXPECT_LE(p.angle_distortion_deg.mean, 0.5 * q.angle_distortion_deg.mean);
        EXPECT_LT(p.conformal_energy, q.conformal_energy);
    }
}

// The GPU ray caster against geo::TriangleBvh: the same face and the same t for every nearest hit,
// the same number of crossings, including rays through the corners and edges of a closed mesh.
#include "flat_box_rays.h"
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/bvh.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/raycast.h"

#include <glm/geometric.hpp>

#include <random>

using namespace gimg;

namespace {

class Raycast : public gimg::test::GpuTest {
protected:
    // Random rays from around the mesh's box through it, and rays aimed at its corners and edge
    // midpoints from outside.
    static std::vector<geo::Ray> rays_for(const geo::Mesh& m, bool front) {
        const geo::Bounds b = m.bounds();
        const glm::dvec3 c = 0.5 * (b.min + b.max);
        const double r = b.diagonal();
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        std::vector<geo::Ray> rays;
        for (int i = 0; i < 3000; ++i) {
            geo::Ray ray;
            ray.origin = c + r * glm::dvec3(u(rng), u(rng), u(rng));
            const glm::dvec3 target = c + 0.3 * r * glm::dvec3(u(rng), u(rng), u(rng));
            ray.direction = target - ray.origin;
            if (i % 5 == 0) ray.t_min = -0.5, ray.t_max = 0.8;  // segments, some starting inside
            ray.front_faces_only = front;
            rays.push_back(ray);
        }
        for (std::size_t f = 0; f < m.face_count() && f < 600; f += 3) {
            const glm::uvec3& t = m.triangles[f];
            for (const glm::dvec3& p : {m.positions[t.x], 0.5 * (m.positions[t.x] + m.positions[t.y])}) {
                geo::Ray ray;
                ray.origin = p + 2.0 * r * glm::normalize(p - c + glm::dvec3(1e-3, 2e-3, 0.0));
                ray.direction = p - ray.origin;
                ray.t_max = 10.0;
                ray.front_faces_only = front;
                rays.push_back(ray);
            }
        }
        return rays;
    }

    void expect_equal(const geo::Mesh& m, const passes::GpuRayCasterOptions& options = {},
                      std::vector<geo::Ray> (*make_rays)(const geo::Mesh&, bool) = rays_for) {
        const geo::TriangleBvh bvh(m);
        passes::GpuRayCaster gpu(ctx(), m, options);
        for (bool front : {false, true}) {
            const std::vector<geo::Ray> rays = make_rays(m, front);
            const auto hits = gpu.nearest(rays);
            std::size_t found = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const auto cpu = bvh.intersect_nearest(rays[i]);
                ASSERT_EQ(hits[i].found(), cpu.has_value()) << "ray " << i;
                if (!cpu) continue;
                ++found;
                ASSERT_EQ(hits[i].face, cpu->face) << "ray " << i;
                ASSERT_EQ(hits[i].t, cpu->t) << "ray " << i;
            }
            EXPECT_GT(found, rays.size() / 4);
        }
        const std::vector<geo::Ray> rays = make_rays(m, false);
        const auto counts = gpu.crossings(rays);
        std::size_t odd = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const auto hits = bvh.intersect_all(rays[i]);
            std::uint32_t n = 0;
            for (std::size_t k = 0; k < hits.size(); ++k)
                if (k == 0 || hits[k].t - hits[k - 1].t > 1e-12) ++n;
            ASSERT_EQ(counts[i], n) << "ray " << i;
            odd += n % 2;
        }
        EXPECT_GT(odd, 0u);  // the segments starting inside
    }
};

}  // namespace

TEST_F(Raycast, GpuEqualsTheBvhOnASphere) { expect_equal(geo::make_icosphere(1.0, 3)); }

TEST_F(Raycast, GpuEqualsTheBvhWithoutSubgroupVotes) {
    expect_equal(geo::make_icosphere(1.0, 3), {.subgroup_votes = false});
}

// Timestamps only when asked: lavapipe pays for them on every pass.
TEST_F(Raycast, TheCallIsTimedOnlyWhenAsked) {
    if (ctx().device_info().timestamp_period_ns <= 0.0) GTEST_SKIP() << "the device has no timestamps";
    const geo::Mesh m = geo::make_icosphere(1.0, 2);
    std::vector<geo::Ray> rays(64);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        rays[i].origin = {3.0, 0.01 * double(i), 0.0};
        rays[i].direction = {-1.0, 0.0, 0.0};
        rays[i].t_max = 10.0;
    }
    passes::GpuRayCaster plain(ctx(), m), timed(ctx(), m, {.timestamps = true});
    EXPECT_EQ(plain.nearest(rays).size(), rays.size());
    EXPECT_EQ(timed.nearest(rays).size(), rays.size());
    EXPECT_EQ(plain.last_gpu_ms(), 0.0);
    EXPECT_GT(timed.last_gpu_ms(), 0.0);
}

// The BVH's own test checks these rays against a scan over every face.
TEST_F(Raycast, FloatBoxTestsLoseNoHitOnAxisAlignedFaces) {
    geo::Mesh box = geo::make_box({2.0, 1.0, 0.5}, 6);
    for (int far = 0; far < 2; ++far) {
        // Far from the origin the boxes' float coordinates are coarse.
        if (far) {
            for (glm::dvec3& p : box.positions) p += glm::dvec3(1000.0, -2000.0, 500.0);
        }
        expect_equal(box, {}, gimg::test::flat_box_rays);
    }
}

TEST_F(Raycast, RaysThroughCornersOfAClosedMeshCrossItTwice) {
    // From far outside through a corner of an icosahedron and on through its centre: in and out.
    const geo::Mesh m = geo::make_icosphere(1.0, 0);
    passes::GpuRayCaster gpu(ctx(), m);
    std::vector<geo::Ray> rays;
    for (const glm::dvec3& p : m.positions) {
        geo::Ray ray;
        ray.origin = 3.0 * p;
        ray.direction = -p;
        ray.t_max = 10.0;
        rays.push_back(ray);
    }
    for (std::uint32_t c : gpu.crossings(rays)) EXPECT_EQ(c, 2u);
}

// More crossings than the walk keeps (kMaxHits, 64) are counted in order: 100 parallel sheets, two
// of them coincident and two 1e-13 apart (each pair one crossing), and rays that cross some.
TEST_F(Raycast, CrossingsBeyondWhatTheWalkKeepsAreCountedAlike) {
    geo::Mesh sheets;
    for (int k = 0; k < 100; ++k) {
        const double x = k == 51 ? 0.50 : k == 71 ? 0.70 + 1e-13 : 0.01 * k;
        const auto first = std::uint32_t(sheets.positions.size());
        for (const glm::dvec2& c : {glm::dvec2(-1, -1), glm::dvec2(1, -1), glm::dvec2(1, 1), glm::dvec2(-1, 1)})
            sheets.positions.push_back({x, c.x, c.y});
        sheets.triangles.push_back({first, first + 1, first + 2});
        sheets.triangles.push_back({first, first + 2, first + 3});
    }
    const geo::TriangleBvh bvh(sheets);
    passes::GpuRayCaster gpu(ctx(), sheets);
    std::vector<geo::Ray> rays;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-0.9, 0.9);
    for (int i = 0; i < 200; ++i) {
        geo::Ray ray;
        ray.origin = {-0.5, u(rng), u(rng)};
        ray.direction = {2.0, 0.1 * u(rng), 0.1 * u(rng)};
        ray.t_min = i % 4 == 0 ? 0.3 : 0.0;
        rays.push_back(ray);
    }
    const std::vector<std::uint32_t> counts = gpu.crossings(rays);
    for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(counts[i], bvh.crossings(rays[i])) << "ray " << i;
    EXPECT_EQ(counts[1], 98u);  // 100 sheets, two pairs counted once
}

TEST_F(Raycast, GpuEqualsTheBvhOnSharedMeshes) {
    for (const char* name : {"bunny.off", "armadillo.off"}) {
        const auto path = gimg::test::shared_mesh(name);
        if (!path) GTEST_SKIP() << "../shared/meshes/" << name << " not present";
        expect_equal(geo::load_mesh(*path));
    }
}

TEST_F(Raycast, CylinderImageOnTheGpuEqualsTheCpuRayCaster) {
    std::vector<geo::Mesh> meshes{geo::make_torus(0.3, 0.1, 48, 24), geo::make_icosphere(0.4, 3)};
    if (const auto path = gimg::test::shared_mesh("bunny.off")) meshes.push_back(geo::load_mesh(*path));
    for (const geo::Mesh& m : meshes) {
        const passes::CylinderMesh cyl = passes::make_cylinder_mesh(m, passes::fit_cylinder_frame(m));
        const passes::CylinderImage cpu = passes::cylinder_raycast(cyl, 180, 90);
        const passes::CylinderImage gpu = passes::cylinder_raycast_gpu(ctx(), cyl, 180, 90);
        ASSERT_EQ(gpu.covered, cpu.covered);
        ASSERT_EQ(gpu.distance, cpu.distance);
        std::size_t covered = 0;
        for (auto c : cpu.covered) covered += c;
        EXPECT_GT(covered, 1000u);
    }
}

// Batch mode: many images (rotations of one mesh, several meshes) in one graph execution, each
// equal to projecting it alone.
#include "cylinder_cases.h"
#include "gpu_test.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/cylinder.h"

#include <glm/ext/matrix_transform.hpp>

#include <algorithm>

using namespace gimg;

namespace {
class CylinderBatch : public gimg::test::GpuTest {};

passes::CylinderTransform rotation_about_z(double degrees) {
    // Rotate about the horizontal z axis through (0, 0.5, 0): the image changes a lot.
    const glm::dmat4 m = glm::translate(glm::dmat4(1.0), {0, 0.5, 0}) *
                         glm::rotate(glm::dmat4(1.0), glm::radians(degrees), {0, 0, 1}) *
                         glm::translate(glm::dmat4(1.0), {0, -0.5, 0});
    return passes::to_cylinder_transform(m);
}
}  // namespace

TEST_F(CylinderBatch, RotationsAndMeshesInOneExecutionEqualSingleProjections) {
    // The default split, large pieces through the graphics pipeline, every piece through the
    // large-piece compute pass (whose rectangles name their image).
    using passes::CylinderLargePieces;
    for (const passes::CylinderZBufferOptions& options :
         {passes::CylinderZBufferOptions{},
          passes::CylinderZBufferOptions{.large_pieces = CylinderLargePieces::Graphics},
          passes::CylinderZBufferOptions{.small_pixels = 0, .large_pieces = CylinderLargePieces::Compute}}) {
        const std::uint32_t W = 96, H = 48;
        passes::CylinderZBuffer z(ctx(), W, H, options);
        const auto torus = z.add_mesh(gimg::test::to_cylinder_mesh(
            geo::make_torus(0.3, 0.1, 24, 12)));  // centred at the origin: moved by the transforms
        const auto box = z.add_mesh(gimg::test::to_cylinder_mesh(geo::make_box({0.5, 0.3, 0.2}, 2)));
        std::vector<passes::CylinderZBuffer::Job> jobs;
        for (int k = 0; k < 40; ++k) {
            auto t = rotation_about_z(9.0 * k);
            t[7] += 0.5f;  // lift into the cylinder
            jobs.push_back({k % 3 == 2 ? box : torus, t});
        }
        const auto batch = z.project(jobs);
        ASSERT_EQ(batch.size(), jobs.size());
        std::size_t covered = 0;
        for (std::size_t k = 0; k < jobs.size(); ++k) {
            const auto single = z.project(jobs[k].mesh, jobs[k].transform);
            ASSERT_EQ(batch[k].covered, single.covered) << "image " << k;
            ASSERT_EQ(batch[k].distance, single.distance) << "image " << k;
            for (auto c : single.covered) covered += c;
        }
        EXPECT_GT(covered, 40u * 300u);
        // Different rotations give different pictures.
        EXPECT_NE(batch[0].covered, batch[1].covered);
    }
}

TEST_F(CylinderBatch, BatchesLargerThanOneExecutionAreSplitAndStayEqual) {
    // 28 x 81,920 faces need more rectangle storage than lavapipe binds at once (128 MiB), so the
    // batch runs as two executions; every image must still equal its single projection.
    const std::uint32_t W = 64, H = 32;
    passes::CylinderZBuffer z(ctx(), W, H);
    const auto sphere = z.add_mesh(gimg::test::to_cylinder_mesh(geo::make_icosphere(0.3, 6, {0.0, 0.0, 0.0})));
    std::vector<passes::CylinderZBuffer::Job> jobs;
    for (int k = 0; k < 28; ++k) {
        passes::CylinderTransform t = passes::kIdentityTransform;
        t[3] = 0.02f * float(k % 5);  // shift in x: different pictures
        t[7] = 0.5f;
        jobs.push_back({sphere, t});
    }
    const auto batch = z.project(jobs);
    ASSERT_EQ(batch.size(), jobs.size());
    for (std::size_t k : {std::size_t(0), std::size_t(13), std::size_t(27)}) {
        const auto single = z.project(jobs[k].mesh, jobs[k].transform);
        EXPECT_EQ(batch[k].covered, single.covered) << "image " << k;
        EXPECT_EQ(batch[k].distance, single.distance) << "image " << k;
    }
}

TEST_F(CylinderBatch, TimestampsOnlyWhenAskedForAndTheSameImage) {
    // GPU times cost lavapipe 0.5 ms a projection, so they are off unless asked for; the image
    // must not depend on them.
    if (ctx().device_info().timestamp_period_ns == 0.0) GTEST_SKIP() << "device has no timestamps";
    const auto mesh = gimg::test::to_cylinder_mesh(geo::make_torus(0.3, 0.1, 24, 12));
    passes::CylinderTransform t = passes::kIdentityTransform;
    t[7] = 0.5f;
    passes::CylinderZBuffer plain(ctx(), 64, 32), timed(ctx(), 64, 32, {.timestamps = true});
    const auto a = plain.project(plain.add_mesh(mesh), t);
    const auto b = timed.project(timed.add_mesh(mesh), t);
    EXPECT_EQ(plain.last_gpu_ms(), 0.0);
    EXPECT_TRUE(plain.last_pass_timings().empty());
    EXPECT_GT(timed.last_gpu_ms(), 0.0);
    EXPECT_FALSE(timed.last_pass_timings().empty());
    EXPECT_EQ(a.covered, b.covered);
    EXPECT_EQ(a.distance, b.distance);
}

TEST_F(CylinderBatch, MeshesAddedTogetherProjectAsAddedOneByOne) {
    // add_meshes prepares the meshes on every core; the images are those of add_mesh, and a bad mesh
    // in the list adds none of them.
    const std::uint32_t W = 64, H = 32;
    std::vector<passes::CylinderMesh> meshes;
    for (int k = 0; k < 7; ++k) {
        geo::Mesh m = k % 2 ? geo::make_torus(0.3, 0.1, 20 + k, 10) : geo::make_icosphere(0.2 + 0.02 * k, 2);
        for (auto& p : m.positions) p.y += 0.5;
        meshes.push_back(gimg::test::to_cylinder_mesh(m));
    }
    passes::CylinderZBuffer together(ctx(), W, H), alone(ctx(), W, H);
    together.reserve(1000, 1000);  // smaller than they need: only a hint
    const std::vector<std::uint32_t> ids = together.add_meshes(meshes);
    ASSERT_EQ(ids.size(), meshes.size());
    for (std::size_t k = 0; k < meshes.size(); ++k) {
        EXPECT_EQ(ids[k], k);
        const auto a = together.project(ids[k]), b = alone.project(alone.add_mesh(meshes[k]));
        EXPECT_GT(std::count(a.covered.begin(), a.covered.end(), 1), 100) << "mesh " << k;
        EXPECT_EQ(a.covered, b.covered) << "mesh " << k;
        EXPECT_EQ(a.distance, b.distance) << "mesh " << k;
    }
    std::vector<passes::CylinderMesh> bad = meshes;
    bad[4].triangles[5] = 1u << 20;
    EXPECT_THROW(together.add_meshes(bad), geo::InputError);
    EXPECT_EQ(together.add_mesh(meshes[0]), meshes.size());  // nothing of the bad list was added
}

// Batch mode: many images (rotations of one mesh, several meshes) in one graph execution, each
// equal to projecting it alone.
#include "cylinder_cases.h"
#include "gpu_test.h"

#include "gimg/passes/cylinder.h"

#include <glm/ext/matrix_transform.hpp>

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

// The graph entry points: cylindrical projection and reconstruction recorded into one caller's
// graph, with nothing passing through host memory between them, give the mesh the two separate
// calls give.
#include "cylinder_cases.h"
#include "gpu_test.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/reconstruct.h"

#include <glm/ext/matrix_transform.hpp>

#include <cmath>
#include <memory>

using namespace gimg;

namespace {

class CylinderGraph : public gimg::test::GpuTest, public ::testing::WithParamInterface<passes::CylinderLargePieces> {};

// A tipped torus with a box beside it: from the cylinder's wall the box hides part of the torus,
// so the reconstruction's threshold cuts blocks where the line jumps from one to the other.
geo::Mesh torus_and_box() {
    geo::Mesh m = geo::make_torus(0.3, 0.1, 64, 24);
    const glm::dmat4 r = glm::rotate(glm::dmat4(1.0), glm::radians(60.0), {1, 0, 0});
    for (auto& p : m.positions) p = glm::dvec3(r * glm::dvec4(p, 1.0));
    m.normals.clear();
    const geo::Mesh box = geo::make_box({0.15, 0.15, 0.15}, 3);
    const auto first = std::uint32_t(m.positions.size());
    for (const auto& p : box.positions) m.positions.push_back(p + glm::dvec3(0.55, 0.0, 0.0));
    for (const auto& t : box.triangles) m.triangles.push_back(t + glm::uvec3(first));
    return m;
}

void expect_same_mesh(const geo::Mesh& a, const geo::Mesh& b) {
    ASSERT_EQ(a.positions.size(), b.positions.size());
    ASSERT_EQ(a.triangles, b.triangles);
    for (std::size_t i = 0; i < a.positions.size(); ++i) ASSERT_EQ(a.positions[i], b.positions[i]) << "vertex " << i;
}

}  // namespace

TEST_P(CylinderGraph, ProjectionAndReconstructionInOneGraphEqualTheSeparateCalls) {
    const geo::Mesh mesh = torus_and_box();
    const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
    passes::CylinderZBuffer z(ctx(), 128, 64, {.large_pieces = GetParam()});
    const std::uint32_t id = z.add_mesh(passes::make_cylinder_mesh(mesh, frame));

    // Separately: the image to the host, then back to the GPU for reconstruction.
    const passes::CylinderImage image = z.project(id);
    const float threshold = passes::default_cylinder_threshold(image);
    passes::ReconstructStats stats;
    const geo::Mesh separate = passes::reconstruct_gpu(ctx(), image, frame, {.threshold = threshold}, &stats);
    ASSERT_GT(separate.face_count(), 4000u);
    ASSERT_GT(stats.holes, 0u) << "the case should exercise the occlusion threshold";

    // Chained: one graph, its only host reads the reconstructed mesh.
    Graph g(ctx());
    const passes::CylinderZBuffer::Job job{id, passes::kIdentityTransform};
    const passes::CylinderImagesHandle images = passes::add_cylinder(g, z, std::span(&job, 1));
    const passes::ReconstructHandles h = passes::add_reconstruct(g, images, 0, frame, threshold);
    passes::export_reconstruction(g, h);
    Plan plan = g.compile();
    plan.execute();
    expect_same_mesh(passes::read_reconstruction(ctx(), plan, h), separate);
    // The plan runs again with the same result.
    plan.execute();
    expect_same_mesh(passes::read_reconstruction(ctx(), plan, h), separate);
}

TEST_P(CylinderGraph, RecordedImagesEqualProjectAndThePlanOutlivesTheZBuffer) {
    const geo::Mesh mesh = torus_and_box();
    const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
    const std::uint32_t W = 96, H = 48;
    auto z = std::make_unique<passes::CylinderZBuffer>(ctx(), W, H,
                                                       passes::CylinderZBufferOptions{.large_pieces = GetParam()});
    const std::uint32_t torus = z->add_mesh(passes::make_cylinder_mesh(mesh, frame));
    const std::uint32_t box = z->add_mesh(gimg::test::to_cylinder_mesh(geo::make_box({0.5, 0.3, 0.2}, 2)));
    passes::CylinderTransform lifted = passes::kIdentityTransform;
    lifted[7] = 0.5f;  // the box is centred at the origin: lift it into the cylinder
    const std::vector<passes::CylinderZBuffer::Job> jobs{
        {torus, passes::kIdentityTransform}, {box, lifted}, {torus, lifted}};
    const std::vector<passes::CylinderImage> expected = z->project(jobs);

    Graph g(ctx());
    const passes::CylinderImagesHandle images = passes::add_cylinder(g, *z, jobs);
    ASSERT_EQ(images.count, 3u);
    // The box's image (the second of three) reconstructed in the same graph; the box was projected
    // as given, so its frame is the identity.
    const float threshold = passes::default_cylinder_threshold(expected[1]);
    const passes::ReconstructHandles h = passes::add_reconstruct(g, images, 1, passes::CylinderFrame{}, threshold);
    passes::export_reconstruction(g, h);
    g.export_buffer(images.distance, Access::TransferSrc);
    Plan plan = g.compile();
    z.reset();  // the plan keeps the meshes and the batch it reads
    plan.execute();
    std::vector<float> d(std::size_t(W) * H * 3);
    ctx().download(plan.buffer(images.distance), d.data(), d.size() * 4);
    std::size_t covered = 0;
    for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t i = 0; i < std::size_t(W) * H; ++i) {
            const float got = d[k * W * H + i];
            ASSERT_EQ(!std::isnan(got), bool(expected[k].covered[i])) << "image " << k << " pixel " << i;
            if (expected[k].covered[i]) {
                ASSERT_EQ(got, expected[k].distance[i]) << "image " << k << " pixel " << i;
                ++covered;
            }
        }
    EXPECT_GT(covered, 3000u);
    expect_same_mesh(passes::read_reconstruction(ctx(), plan, h),
                     passes::reconstruct_gpu(ctx(), expected[1], passes::CylinderFrame{}, {.threshold = threshold}));
}

TEST_P(CylinderGraph, BadIdsAndIndicesAreInputErrors) {
    passes::CylinderZBuffer z(ctx(), 32, 16, {.large_pieces = GetParam()});
    const std::uint32_t id = z.add_mesh(gimg::test::to_cylinder_mesh(geo::make_box({0.5, 0.3, 0.2}, 1)));
    Graph g(ctx());
    const passes::CylinderZBuffer::Job bad{id + 1, passes::kIdentityTransform};
    EXPECT_THROW(passes::add_cylinder(g, z, std::span(&bad, 1)), geo::InputError);
    EXPECT_THROW(passes::add_cylinder(g, z, {}), geo::InputError);
    const passes::CylinderZBuffer::Job good{id, passes::kIdentityTransform};
    const auto images = passes::add_cylinder(g, z, std::span(&good, 1));
    EXPECT_THROW(passes::add_reconstruct(g, images, 1, passes::CylinderFrame{}, 1.0f), geo::InputError);
}

INSTANTIATE_TEST_SUITE_P(LargePieces, CylinderGraph,
                         ::testing::Values(passes::CylinderLargePieces::Compute, passes::CylinderLargePieces::Graphics),
                         [](const auto& param_info) {
                             return param_info.param == passes::CylinderLargePieces::Compute ? "compute" : "graphics";
                         });

// Context::prepare_compute: pipelines made on several threads at once serve the passes recorded
// after them, a shader listed twice is made once, and a failure on a helper thread reaches the caller.
#include "gimg/engine/context.h"
#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"
#include "gimg/engine/upload.h"

#include "gpu_test.h"

#include "engine/jacobi1d_comp.h"
#include "engine/pixel_triangle_vert.h"
#include "engine/scale_add_comp.h"

#include <memory>
#include <string>
#include <vector>

using namespace gimg;

namespace {
class PrepareCompute : public gimg::test::GpuTest {};
const Spirv kScaleAdd = GIMG_SPIRV(gimg_spv_engine_scale_add_comp);
const Spirv kJacobi = GIMG_SPIRV(gimg_spv_engine_jacobi1d_comp);
const Spirv kVertex = GIMG_SPIRV(gimg_spv_engine_pixel_triangle_vert);
struct ScaleAdd {
    std::uint32_t count;
    float scale, offset;
};
}  // namespace

TEST_F(PrepareCompute, PreparedPipelinesServeThePassesRecordedAfter) {
    // A context of its own, so that no earlier test has made these pipelines.
    ContextOptions options = ContextOptions::from_environment();
    options.validation = ctx().validation_enabled();
    const std::unique_ptr<Context> own = Context::create(options);
    own->prepare_compute({kScaleAdd, kJacobi, kScaleAdd});
    own->prepare_compute({kScaleAdd});  // all made: nothing to do

    constexpr std::uint32_t n = 1000;
    std::vector<float> values(n);
    for (std::uint32_t i = 0; i < n; ++i) values[i] = float(i) - 300.0f;
    Buffer src = upload_buffer(*own, values, "src");
    Buffer dst = own->create_buffer({n * sizeof(float), "dst"});
    Graph g(*own);
    auto hs = g.import_buffer(src);
    auto hd = g.import_buffer(dst);
    g.add_compute_pass(
        "scale and add",
        [&](PassBuilder& b) {
            b.read(hs, Access::ComputeRead);
            hd = b.write(hd, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kScaleAdd, {n}, {hs, hd}, ScaleAdd{n, 2.0f, 0.5f});
        });
    Plan plan = g.compile();
    plan.execute();
    const std::vector<float> out = own->download<float>(dst);
    for (std::uint32_t i = 0; i < n; ++i) ASSERT_EQ(out[i], values[i] * 2.0f + 0.5f) << i;
    EXPECT_EQ(own->validation_message_count(), 0u);
}

TEST_F(PrepareCompute, AShaderThatIsNotComputeFailsWithItsName) {
    try {
        ctx().prepare_compute({kScaleAdd, kVertex, kJacobi});
        FAIL() << "a vertex shader cannot make a compute pipeline";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("pixel_triangle"), std::string::npos) << e.what();
    }
}

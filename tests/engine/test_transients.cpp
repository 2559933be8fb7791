// Transient reuse and aliasing on a real device: shared physical resources and memory give the
// right results, execution after execution, with synchronization validation watching.
#include "gimg/engine/graph.h"

#include "gpu_test.h"

#include "engine/scale_add_comp.h"

#include <vector>

using namespace gimg;

class TransientResources : public gimg::test::GpuTest {};

namespace {
const Spirv kScaleAdd = GIMG_SPIRV(gimg_spv_engine_scale_add_comp);
struct ScaleAdd {
    std::uint32_t count;
    float scale, offset;
};

void scale_add(Graph& g, const std::string& name, BufferHandle& src, BufferHandle& dst, std::uint32_t n, float scale,
               float offset) {
    g.add_compute_pass(
        name,
        [&](PassBuilder& b) {
            b.read(src, Access::ComputeRead);
            dst = b.write(dst, Access::ComputeWrite);
        },
        [=, s = src, d = dst](Cmd& c) {
            c.dispatch_threads(kScaleAdd, {n}, {s, d}, ScaleAdd{n, scale, offset});
        });
}
}  // namespace

TEST_F(TransientResources, TwoTransientsWithDisjointLifetimesShareOneResourceAndStayCorrect) {
    constexpr std::uint32_t N = 4096;
    std::vector<float> x(N);
    for (std::uint32_t i = 0; i < N; ++i) x[i] = float(i % 100) * 0.5f;
    Buffer input = ctx().create_buffer({N * 4, "x"});
    Buffer out1 = ctx().create_buffer({N * 4, "out1"}, MemoryUsage::Readback);
    Buffer out2 = ctx().create_buffer({N * 4, "out2"}, MemoryUsage::Readback);
    ctx().upload(input, x.data(), N * 4);

    Graph g(ctx());
    auto in = g.import_buffer(input);
    auto o1 = g.import_buffer(out1);
    auto o2 = g.import_buffer(out2);
    auto t1 = g.create_buffer({N * 4, "t1"});
    auto t2 = g.create_buffer({N * 4, "t2"});
    scale_add(g, "t1 = 2x + 1", in, t1, N, 2.0f, 1.0f);
    scale_add(g, "out1 = t1", t1, o1, N, 1.0f, 0.0f);
    scale_add(g, "t2 = 3x", in, t2, N, 3.0f, 0.0f);
    scale_add(g, "out2 = t2 - 1", t2, o2, N, 1.0f, -1.0f);
    g.export_buffer(o1, Access::HostRead);
    g.export_buffer(o2, Access::HostRead);
    Plan plan = g.compile();
    ASSERT_EQ(*plan.physical_resource(t1), *plan.physical_resource(t2)) << plan.describe();

    for (int run = 0; run < 3; ++run) {
        plan.execute();
        auto r1 = out1.mapped_as<float>(), r2 = out2.mapped_as<float>();
        for (std::uint32_t i = 0; i < N; ++i) {
            ASSERT_EQ(r1[i], 2.0f * x[i] + 1.0f) << "run " << run << " i " << i;
            ASSERT_EQ(r2[i], 3.0f * x[i] - 1.0f) << "run " << run << " i " << i;
        }
    }
}

TEST_F(TransientResources, AliasedTransientsOfDifferentSizesStayCorrect) {
    constexpr std::uint32_t N = 1 << 16;
    std::vector<float> x(N);
    for (std::uint32_t i = 0; i < N; ++i) x[i] = float(i % 1000);
    Buffer input = ctx().create_buffer({N * 4, "x"});
    Buffer output = ctx().create_buffer({N / 4 * 4, "out"}, MemoryUsage::Readback);
    ctx().upload(input, x.data(), N * 4);

    Graph g(ctx());
    auto in = g.import_buffer(input);
    auto out = g.import_buffer(output);
    auto big = g.create_buffer({N * 4, "big"});
    auto mid = g.create_buffer({N / 2 * 4, "mid"});
    auto small = g.create_buffer({N / 4 * 4, "small"});
    scale_add(g, "big = x + 1", in, big, N, 1.0f, 1.0f);
    scale_add(g, "mid = 2 big", big, mid, N / 2, 2.0f, 0.0f);
    scale_add(g, "small = mid + 3", mid, small, N / 4, 1.0f, 3.0f);  // may land on big's memory
    scale_add(g, "out = small", small, out, N / 4, 1.0f, 0.0f);
    g.export_buffer(out, Access::HostRead);
    Plan plan = g.compile();
    const auto pb = *plan.placement(big), ps = *plan.placement(small);
    EXPECT_TRUE(pb.block == ps.block && ps.offset < pb.offset + pb.size && pb.offset < ps.offset + ps.size)
        << "small should alias big's memory:\n"
        << plan.describe();

    for (int run = 0; run < 3; ++run) {
        plan.execute();
        auto r = output.mapped_as<float>();
        for (std::uint32_t i = 0; i < N / 4; ++i) ASSERT_EQ(r[i], 2.0f * (x[i] + 1.0f) + 3.0f) << "run " << run;
    }
}

// A compute chain over 1M elements: fill, inclusive prefix sum and reduction on the GPU, equal to
// the CPU (exact integers).
#include "gimg/passes/primitives.h"

#include "gpu_test.h"

#include "passes/fill_hash_comp.h"

#include <cmath>
#include <numeric>
#include <span>
#include <vector>

using namespace gimg;

namespace {

class Primitives : public gimg::test::GpuTest {};

const Spirv kFillHash = GIMG_SPIRV(gimg_spv_passes_fill_hash_comp);

struct FillPush {
    std::uint32_t count;
    std::uint32_t modulus;
};

// The same hash as the shader.
std::uint32_t hash(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

struct ChainResult {
    std::vector<std::uint32_t> scan;
    std::uint32_t sum;
};

ChainResult run_chain(Context& ctx, std::uint32_t n) {
    Buffer scan_out = ctx.create_buffer({VkDeviceSize(n) * 4, "prefix sums"});
    Buffer sum_out = ctx.create_buffer({4, "sum"}, MemoryUsage::Readback);
    Graph g(ctx);
    auto values = g.create_buffer({VkDeviceSize(n) * 4, "values"});
    auto scan = g.import_buffer(scan_out);
    auto sum = g.import_buffer(sum_out);
    g.add_compute_pass(
        "fill", [&](PassBuilder& b) { values = b.write(values, Access::ComputeWrite); },
        [=](Cmd& c) {
            c.dispatch_threads(kFillHash, {n}, {values}, FillPush{n, 1000});
        });
    scan = passes::add_inclusive_scan(g, values, scan, n);
    sum = passes::add_reduce_sum(g, values, sum, n);
    g.export_buffer(scan, Access::TransferSrc);
    g.export_buffer(sum, Access::HostRead);
    g.compile().execute();
    return {ctx.download<std::uint32_t>(scan_out), sum_out.mapped_as<std::uint32_t>()[0]};
}

void expect_matches_cpu(const ChainResult& gpu, std::uint32_t n) {
    std::vector<std::uint32_t> values(n);
    for (std::uint32_t i = 0; i < n; ++i) values[i] = hash(i) % 1000;
    std::vector<std::uint32_t> scan(n);
    std::inclusive_scan(values.begin(), values.end(), scan.begin());
    ASSERT_EQ(gpu.scan.size(), n);
    std::size_t first_bad = n;
    for (std::uint32_t i = 0; i < n && first_bad == n; ++i)
        if (gpu.scan[i] != scan[i]) first_bad = i;
    EXPECT_EQ(first_bad, n) << "first wrong prefix sum at " << first_bad << " of " << n;
    EXPECT_EQ(gpu.sum, scan.back());
}

}  // namespace

TEST_F(Primitives, FillScanReduceOverOneMillionElementsEqualsTheCpu) {
    const std::uint32_t n = 1u << 20;
    expect_matches_cpu(run_chain(ctx(), n), n);
}

TEST_F(Primitives, OddSizesAcrossBlockAndLevelBoundaries) {
    for (std::uint32_t n : {1u, 1023u, 1024u, 1025u, 1024u * 1024u + 17u}) {
        SCOPED_TRACE(n);
        expect_matches_cpu(run_chain(ctx(), n), n);
    }
}

namespace {

std::vector<double> reduce_f64_on_gpu(Context& ctx, const std::vector<double>& values, std::uint32_t width,
                                      passes::ReduceF64Method method) {
    const auto count = std::uint32_t(values.size() / width);
    Buffer in_buf = ctx.create_buffer({VkDeviceSize(values.size()) * 8, "values"});
    ctx.upload(in_buf, std::span<const double>(values));
    Buffer out_buf = ctx.create_buffer({VkDeviceSize(width) * 8, "sums"}, MemoryUsage::Readback);
    Graph g(ctx);
    auto in = g.import_buffer(in_buf);
    auto out = passes::add_reduce_sum_f64(g, in, g.import_buffer(out_buf), count, width, "sum f64", method);
    g.export_buffer(out, Access::HostRead);
    g.compile().execute();
    const auto sums = out_buf.mapped_as<double>();
    return {sums.begin(), sums.begin() + width};
}

// Both ways of summing a block the device has: the tree everywhere, subgroup arithmetic where there is.
std::vector<passes::ReduceF64Method> reduce_methods(const Context& ctx) {
    if (!ctx.device_info().subgroup_arithmetic) return {passes::ReduceF64Method::tree};
    return {passes::ReduceF64Method::tree, passes::ReduceF64Method::subgroup};
}

}  // namespace

// Multiples of 1/8 below 2^20 sum exactly in double, so the GPU must equal the CPU bit for bit.
TEST_F(Primitives, DoubleReductionOfInterleavedComponentsIsExact) {
    if (!ctx().device_info().shader_float64) GTEST_SKIP() << "device has no shaderFloat64";
    for (passes::ReduceF64Method method : reduce_methods(ctx())) {
        for (std::uint32_t width : {1u, 3u}) {
            for (std::uint32_t n : {1u, 1023u, 1025u, 300000u}) {
                SCOPED_TRACE(testing::Message() << "method " << int(method) << " width " << width << " count " << n);
                std::vector<double> values(std::size_t(n) * width);
                std::vector<double> expected(width, 0.0);
                for (std::size_t i = 0; i < values.size(); ++i) {
                    values[i] = double(hash(std::uint32_t(i)) % 1000) * 0.125 - 60.0;
                    expected[i % width] += values[i];
                }
                EXPECT_EQ(reduce_f64_on_gpu(ctx(), values, width, method), expected);
            }
        }
    }
}

// Lavapipe, where CI runs, has subgroup arithmetic: the fast path is the one tested there.
TEST_F(Primitives, LavapipeTakesTheSubgroupReduction) {
    if (!ctx().device_info().is_lavapipe) GTEST_SKIP() << "not lavapipe";
    EXPECT_TRUE(ctx().device_info().subgroup_arithmetic);
    EXPECT_EQ(reduce_methods(ctx()).size(), 2u);
}

// Values that do not sum exactly: the fixed tree gives the same bits on every run, within
// rounding of a compensated CPU sum.
TEST_F(Primitives, DoubleReductionIsDeterministicAndAccurate) {
    if (!ctx().device_info().shader_float64) GTEST_SKIP() << "device has no shaderFloat64";
    const std::uint32_t n = 200000;
    std::vector<double> values(n);
    for (std::uint32_t i = 0; i < n; ++i) values[i] = std::sin(0.001 * i) * 1e-3 + 1.0 / (1.0 + i);
    long double reference = 0.0L;
    for (double v : values) reference += v;
    for (passes::ReduceF64Method method : reduce_methods(ctx())) {
        SCOPED_TRACE(int(method));
        const auto first = reduce_f64_on_gpu(ctx(), values, 1, method);
        const auto second = reduce_f64_on_gpu(ctx(), values, 1, method);
        EXPECT_EQ(first, second);
        EXPECT_NEAR(first[0], double(reference), 1e-12 * std::abs(double(reference)));
    }
}

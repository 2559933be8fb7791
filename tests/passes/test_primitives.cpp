// A compute chain over 1M elements: fill, inclusive prefix sum and reduction on the GPU, equal to
// the CPU (exact integers).
#include "gimg/passes/primitives.h"

#include "gpu_test.h"

#include "passes/fill_hash_comp.h"

#include <numeric>
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
    g.add_compute_pass("fill", [&](PassBuilder& b) { values = b.write(values, Access::ComputeWrite); },
                       [=](Cmd& c) { c.dispatch_threads(kFillHash, {n}, {values}, FillPush{n, 1000}); });
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

#include "gimg/passes/primitives.h"

#include "gimg/engine/context.h"
#include "gimg/engine/error.h"

#include "primitives/reduce_f64_comp.h"
#include "primitives/reduce_f64_subgroup_comp.h"
#include "primitives/reduce_sum_comp.h"
#include "primitives/scan_add_offsets_comp.h"
#include "primitives/scan_blocks_comp.h"
#include "primitives/scan_config.h"

namespace gimg::passes {

namespace {
const Spirv kScanBlocks = GIMG_SPIRV(gimg_spv_primitives_scan_blocks_comp);
const Spirv kScanAddOffsets = GIMG_SPIRV(gimg_spv_primitives_scan_add_offsets_comp);
const Spirv kReduceSum = GIMG_SPIRV(gimg_spv_primitives_reduce_sum_comp);
const Spirv kReduceF64 = GIMG_SPIRV(gimg_spv_primitives_reduce_f64_comp);
const Spirv kReduceF64Subgroup = GIMG_SPIRV(gimg_spv_primitives_reduce_f64_subgroup_comp);

std::uint32_t blocks_of(std::uint32_t count) { return (count + GIMG_SCAN_BLOCK - 1) / GIMG_SCAN_BLOCK; }

void require_elements(std::uint32_t count, const std::string& name) {
    if (count == 0) throw Error(ErrorKind::InvalidArgument, name + ": nothing to process (count 0)");
}
}  // namespace

BufferHandle add_inclusive_scan(Graph& graph, BufferHandle in, BufferHandle out, std::uint32_t count,
                                const std::string& name) {
    require_elements(count, name);
    const std::uint32_t blocks = blocks_of(count);
    auto block_sums = graph.create_buffer({VkDeviceSize(blocks) * 4, name + " block sums"});
    graph.add_compute_pass(
        name + " blocks",
        [&](PassBuilder& b) {
            b.read(in, Access::ComputeRead);
            out = b.write(out, Access::ComputeWrite);
            block_sums = b.write(block_sums, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch(kScanBlocks, {blocks}, {in, out, block_sums}, count);
        });
    if (blocks == 1) return out;

    // Scan the block totals (recursively: each level divides the count by 1024), then add them.
    auto scanned = graph.create_buffer({VkDeviceSize(blocks) * 4, name + " scanned block sums"});
    scanned = add_inclusive_scan(graph, block_sums, scanned, blocks, name + "/");
    graph.add_compute_pass(
        name + " add offsets",
        [&](PassBuilder& b) {
            out = b.write(out, Access::ComputeReadWrite);
            b.read(scanned, Access::ComputeRead);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kScanAddOffsets, {count}, {out, scanned}, count);
        });
    return out;
}

BufferHandle add_reduce_sum(Graph& graph, BufferHandle in, BufferHandle out, std::uint32_t count,
                            const std::string& name) {
    require_elements(count, name);
    for (int level = 0;; ++level) {
        const std::uint32_t blocks = blocks_of(count);
        const std::string pass = name + " level " + std::to_string(level);
        // The last level (one block) writes the result; earlier ones write per-block partial sums.
        BufferHandle dst = blocks == 1 ? out : graph.create_buffer({VkDeviceSize(blocks) * 4, pass + " partial sums"});
        graph.add_compute_pass(
            pass,
            [&](PassBuilder& b) {
                b.read(in, Access::ComputeRead);
                dst = b.write(dst, Access::ComputeWrite);
            },
            [=](Cmd& c) {
                c.dispatch(kReduceSum, {blocks}, {in, dst}, count);
            });
        if (blocks == 1) return dst;
        in = dst;
        count = blocks;
    }
}

BufferHandle add_reduce_sum_f64(Graph& graph, BufferHandle in, BufferHandle out, std::uint32_t count,
                                std::uint32_t width, const std::string& name, ReduceF64Method method) {
    require_elements(count, name);
    const DeviceInfo* device = graph.device_info();
    const bool subgroups = device && device->subgroup_arithmetic;
    if (method == ReduceF64Method::subgroup && !subgroups)
        throw Error(ErrorKind::Unsupported, name + ": the device has no subgroup arithmetic in compute shaders");
    const Spirv& shader = method == ReduceF64Method::tree || !subgroups ? kReduceF64 : kReduceF64Subgroup;
    struct Push {
        std::uint32_t count, width;
    };
    for (int level = 0;; ++level) {
        const std::uint32_t blocks = blocks_of(count);
        const std::string pass = name + " level " + std::to_string(level);
        BufferHandle dst =
            blocks == 1 ? out : graph.create_buffer({VkDeviceSize(blocks) * 8 * width, pass + " partial sums"});
        graph.add_compute_pass(
            pass,
            [&](PassBuilder& b) {
                b.read(in, Access::ComputeRead);
                dst = b.write(dst, Access::ComputeWrite);
            },
            [=](Cmd& c) {
                c.dispatch(shader, {blocks}, {in, dst}, Push{count, width});
            });
        if (blocks == 1) return dst;
        in = dst;
        count = blocks;
    }
}

}  // namespace gimg::passes

// Decoding a hierarchy on the GPU (shaders/cylinder_hierarchy/decode_level.comp): level one, then
// per level the cells and the edges with the interleave, one graph; the CPU decoder's grid.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/engine/error.h"
#include "gimg/engine/upload.h"
#include "gimg/engine/graph.h"

#include "cylinder_hierarchy/decode_level_comp.h"
#include "launch_rays.h"

#include <algorithm>

namespace gimg::passes {

namespace {

const Spirv kDecodeLevel = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_decode_level_comp);

struct DecodePush {
    std::uint32_t step, side, n, base;
};

}  // namespace

HierarchyGrid decode_cylinder_hierarchy_gpu(Context& ctx, const CylinderHierarchy& h, std::uint32_t level) {
    if (!ctx.device_info().shader_float64)
        throw Error(ErrorKind::Unsupported, "decoding a hierarchy on the GPU needs shaderFloat64 (use the CPU)");
    detail::check_decodable(h, level);
    const std::uint32_t n = h.size, b = h.base;
    std::vector<std::uint32_t> valid(h.valid.begin(), h.valid.end());
    std::vector<double> dirs;
    for (const auto& d : cylinder_directions(b)) dirs.insert(dirs.end(), {d[0], d[1]});
    // The radial samples' directions per next grid of side M, from entry M - B.
    for (std::uint32_t m = 2 * b; m <= n; m *= 2)
        for (const auto& d : detail::radial_directions(m, b)) dirs.insert(dirs.end(), {d[0], d[1]});
    Buffer band_t = upload_buffer(ctx, h.t, "hierarchy t"), band_valid = upload_buffer(ctx, valid, "hierarchy valid"),
           directions = upload_buffer(ctx, dirs, "hierarchy directions");

    Graph g(ctx);
    auto bt = g.import_buffer(band_t), bv = g.import_buffer(band_valid), dr = g.import_buffer(directions);
    auto grid_buffers = [&](std::uint32_t side) {
        const VkDeviceSize points = VkDeviceSize(side) * side;
        return std::pair{g.create_buffer({points * 32, "hierarchy grid"}), g.create_buffer({points * 4, "grid valid"})};
    };
    auto [grid, grid_valid] = grid_buffers(b);
    // Each step binds every buffer; the ones a step does not touch are written so they are defined.
    auto step = [&](std::uint32_t which, std::uint32_t side, BufferHandle& cur, BufferHandle& cur_valid,
                    BufferHandle& cells, BufferHandle& next, BufferHandle& next_valid) {
        const DecodePush push{which, side, n, b};
        g.add_compute_pass(
            "decode hierarchy: step " + std::to_string(which) + " at " + std::to_string(side),
            [&](PassBuilder& pb) {
                for (auto hnd : {bt, bv, dr}) pb.read(hnd, Access::ComputeRead);
                if (which == 0) {
                    cur = pb.write(cur, Access::ComputeWrite);
                    cur_valid = pb.write(cur_valid, Access::ComputeWrite);
                } else {
                    pb.read(cur, Access::ComputeRead);
                    pb.read(cur_valid, Access::ComputeRead);
                }
                cells = pb.write(cells, which == 2 ? Access::ComputeReadWrite : Access::ComputeWrite);
                next = pb.write(next, Access::ComputeWrite);
                next_valid = pb.write(next_valid, Access::ComputeWrite);
            },
            [=, c0 = cur, c1 = cur_valid, ce = cells, nx = next, nv = next_valid](Cmd& c) {
                c.dispatch_threads(kDecodeLevel, {side, side}, {bt, bv, dr, c0, c1, ce, nx, nv}, push);
            });
    };
    std::uint32_t side = b;
    for (std::uint32_t l = 1; l <= level; ++l, side *= 2) {
        auto cells = g.create_buffer({VkDeviceSize(side) * side * 64, "hierarchy cells"});
        auto [next, next_valid] = grid_buffers(2 * side);
        if (l == 1) step(0, side, grid, grid_valid, cells, next, next_valid);
        if (l == level) break;
        step(1, side, grid, grid_valid, cells, next, next_valid);
        step(2, side, grid, grid_valid, cells, next, next_valid);
        grid = next;
        grid_valid = next_valid;
    }
    g.export_buffer(grid, Access::TransferSrc);
    g.export_buffer(grid_valid, Access::TransferSrc);
    Plan plan = g.compile();
    plan.execute();

    HierarchyGrid out;
    out.side = side;
    out.base = b;
    const std::size_t count = std::size_t(side) * side;
    std::vector<double> points(4 * count);
    std::vector<std::uint32_t> kinds(count);
    ctx.download(plan.buffer(grid), points.data(), points.size() * 8);
    ctx.download(plan.buffer(grid_valid), kinds.data(), kinds.size() * 4);
    out.points.resize(count);
    out.valid.resize(count);
    out.outward.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        out.points[i] = {points[4 * i], points[4 * i + 1], points[4 * i + 2]};
        out.valid[i] = std::uint8_t(kinds[i]);
        out.outward[i] = points[4 * i + 3] >= 0.0 ? 1 : -1;
    }
    return out;
}

}  // namespace gimg::passes

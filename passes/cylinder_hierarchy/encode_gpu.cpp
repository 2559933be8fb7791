// The hierarchy's GPU encoder: the GpuRayCaster's tree, then every level in one submission: level 1's
// rays (cast_level_one.comp), and per later level two passes: the grid's cells (grid_cells.comp)
// and the level's rays with their launches, parity segments, misses, stored samples and the next
// grid built from them as the decoder builds it (cast_level.comp). The CPU encoder's hierarchy bit
// for bit.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/engine/error.h"
#include "gimg/engine/texel_array.h"
#include "gimg/engine/upload.h"
#include "gimg/passes/raycast.h"

#include "cylinder_hierarchy/cast_level_comp.h"
#include "cylinder_hierarchy/cast_level_one_comp.h"
#include "cylinder_hierarchy/cast_level_one_plain_comp.h"
#include "cylinder_hierarchy/cast_level_plain_comp.h"
#include "encode.h"
#include "level_passes.h"
#include "ray_rules.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>

namespace gimg::passes {

namespace {

const Spirv kCastLevel = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_cast_level_comp);
const Spirv kCastLevelPlain = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_cast_level_plain_comp);
const Spirv kCastLevelOne = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_cast_level_one_comp);
const Spirv kCastLevelOnePlain = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_cast_level_one_plain_comp);

struct CastPush {
    std::uint32_t side, n, base, miss, write_next;
    float scene;
    double behind, reach;
};
static_assert(offsetof(CastPush, behind) == 24 && sizeof(CastPush) == 40, "cast_level.glsl's push constants");

std::uint32_t miss_code(HierarchyMiss miss) {
    return miss == HierarchyMiss::Surface ? 0u : miss == HierarchyMiss::Invalid ? 1u : 2u;
}

// Level L's passes are named "hierarchy level L: ..." (their timings are summed by the number).
constexpr std::string_view kLevelPrefix = "hierarchy level ";
std::string level_name(std::uint32_t level) { return std::string(kLevelPrefix) + std::to_string(level) + ": "; }

}  // namespace

std::vector<double> hierarchy_directions(std::uint32_t base, std::uint32_t size) {
    check_hierarchy_sizes(base, size);
    return detail::level_directions(base, size);
}

ImageHandle add_cylinder_hierarchy(Graph& g, GpuRayCaster& caster, ImageHandle bands, BufferHandle directions,
                                   const CylinderHierarchyOptions& options) {
    check_hierarchy_sizes(options.base, options.size);
    detail::check_reach(options.reach);
    const std::uint32_t b = options.base, n = options.size;
    const RaycastTree tree = import_raycast_tree(g, caster);
    detail::LevelBuffers lb{.bands = bands, .directions = directions};
    auto unused = [&] { return g.create_image(texel_array_desc(0, Format::RGBA32U, "unused")); };
    // Level `level`'s rays from the grid of side `side` (level 1: the B x B image's), writing the
    // bands and, unless it is the last level, the next grid.
    auto add_cast = [&](std::uint32_t level, std::uint32_t side) {
        const bool first = level == 1, write_next = (first ? side : 2 * side) < n;
        const std::size_t next_points = std::size_t(first ? side : 2 * side) * (first ? side : 2 * side);
        const CastPush push{
            side, n, b, miss_code(options.miss), write_next ? 1u : 0u, tree.scene, detail::kBehind, options.reach};
        const Spirv& kernel =
            first ? (tree.votes ? kCastLevelOne : kCastLevelOnePlain) : (tree.votes ? kCastLevel : kCastLevelPlain);
        // Level 1 reads no grid: one-row stand-ins take the grid's and the cells' bindings.
        ImageHandle grid = first ? unused() : lb.grid, cells = first ? unused() : lb.cells;
        ImageHandle next =
            write_next ? g.create_image(texel_array_desc(2 * next_points, Format::RGBA32U, "hierarchy grid")) : unused();
        g.add_compute_pass(
            level_name(level) + "rays",
            [&](PassBuilder& pb) {
                for (auto hnd : {tree.nodes, tree.corners}) pb.read(hnd, Access::ComputeRead);
                for (ImageHandle* hnd : {&grid, &cells})
                    if (first)  // the shader may read them, as far as validation can tell
                        *hnd = pb.write(*hnd, Access::ComputeReadWrite);
                    else
                        pb.read(*hnd, Access::ComputeRead);
                pb.read(tree.faces, Access::ComputeRead);
                pb.read(lb.directions, Access::ComputeRead);
                // Read-write after level 1: the earlier levels' samples stay.
                lb.bands = pb.write(lb.bands, first ? Access::ComputeWrite : Access::ComputeReadWrite);
                next = pb.write(next, Access::ComputeWrite);
            },
            [=, out = lb.bands, dirs = lb.directions](Cmd& c) {
                c.dispatch_threads(kernel, {side, side, first ? 1u : 3u},
                                   {tree.nodes, tree.corners, tree.faces, dirs, grid, cells, out, next}, push);
            });
        lb.grid = next;
    };
    add_cast(1, b);
    std::uint32_t level = 2;
    for (std::uint32_t s = b; s < n; s *= 2, ++level) {
        detail::add_level_step(g, 1, s, n, b, lb, level_name(level) + "cells");
        add_cast(level, s);
    }
    return lb.bands;
}

CylinderHierarchy cylinder_hierarchy_gpu(Context& ctx, const CylinderMesh& mesh,
                                         const CylinderHierarchyOptions& options, const GpuRayCasterOptions& walk) {
    check_hierarchy_sizes(options.base, options.size);
    const std::uint32_t b = options.base, n = options.size;
    // The largest texel array: the cells of the grid of side N / 2, 4 texels each.
    detail::check_level_images(ctx, std::size_t(n) * n, n, "the GPU encoder at " + std::to_string(n) + " x " + std::to_string(n));
    CylinderHierarchy h = detail::empty_hierarchy(options);
    // The pipelines first, on every core at once (lavapipe: about 20 ms for each cast shader).
    const auto prepare_start = std::chrono::steady_clock::now();
    const bool votes = walk.subgroup_votes && ctx.device_info().subgroup_vote;
    ctx.prepare_compute({votes ? kCastLevelOne : kCastLevelOnePlain, votes ? kCastLevel : kCastLevelPlain,
                         detail::level_step_kernel(1)});
    h.pipeline_ms = detail::ms_since(prepare_start);
    // The BVH every level casts through counts as level 1's time.
    const auto start = std::chrono::steady_clock::now();
    GpuRayCaster caster(ctx, to_cylinder_frame(mesh), walk);
    const double tree_ms = detail::ms_since(start);
    const auto cast_start = std::chrono::steady_clock::now();
    Image bands = ctx.create_image({n, n, Format::RG32U, "hierarchy bands"});  // every sample is written
    Buffer directions = upload_buffer(ctx, detail::level_directions(b, n), "hierarchy directions");
    Buffer readback;
    Graph g(ctx);
    const ImageHandle out =
        add_cylinder_hierarchy(g, caster, g.import_image(bands), g.import_buffer(directions), options);
    detail::add_read_back(ctx, g, out, readback, level_name(h.levels()) + "read back");
    Plan plan = g.compile();
    const bool timed = options.timestamps && ctx.device_info().timestamp_period_ns > 0.0;
    plan.execute({.wait = true, .timestamps = timed});
    detail::read_bands(ctx, readback, h);

    // One submission: each level's passes by their timestamps (level 1's after the tree's upload),
    // and what else the submission took (recording, waiting, the download) counted in the last
    // level; untimed, level 1 holds the tree and the last level the whole submission.
    const double cast_ms = detail::ms_since(cast_start);
    std::vector<double> per_level(h.levels() + 1, 0.0);
    if (timed)
        for (const PassTiming& t : plan.timings())
            per_level[std::stoul(t.name.substr(kLevelPrefix.size()))] += t.gpu_ms;
    h.level_ms.assign(per_level.begin() + 1, per_level.end());
    h.level_ms.front() += tree_ms;
    h.tree_ms = tree_ms;
    double passes_ms = 0.0;
    for (double ms : h.level_ms) passes_ms += ms;
    h.level_ms.back() += std::max(0.0, tree_ms + cast_ms - passes_ms);
    h.gpu_ms = timed ? plan.total_gpu_ms() : 0.0;
    return h;
}

}  // namespace gimg::passes

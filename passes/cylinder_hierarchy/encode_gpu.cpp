// The hierarchy's GPU encoder: level 1 by the GPU ray caster, then every later level in one
// submission, three passes a level: the grid's cells (decode_level.comp), the level's rays with
// their launches, parity segments, misses and stored values (cast_level.glsl), and the next grid
// from the stored values (decode_level.comp, as the decoder builds it). The CPU encoder's
// hierarchy bit for bit, with one round trip after level 1.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/engine/error.h"
#include "gimg/engine/upload.h"
#include "gimg/passes/raycast.h"

#include "cylinder_hierarchy/cast_level_comp.h"
#include "cylinder_hierarchy/cast_level_plain_comp.h"
#include "encode.h"
#include "level_passes.h"
#include "ray_rules.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

namespace gimg::passes {

namespace {

const Spirv kCastLevel = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_cast_level_comp);
const Spirv kCastLevelPlain = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_cast_level_plain_comp);

struct CastPush {
    std::uint32_t side, n, base, miss;
    float scene;
    double behind, reach;
};
static_assert(offsetof(CastPush, behind) == 24 && sizeof(CastPush) == 40, "cast_level.glsl's push constants");

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

std::uint32_t miss_code(HierarchyMiss miss) {
    return miss == HierarchyMiss::Surface ? 0u : miss == HierarchyMiss::Invalid ? 1u : 2u;
}

// Level L's passes are named "hierarchy level L: ..." (their timings are summed by the number).
constexpr std::string_view kLevelPrefix = "hierarchy level ";
std::string level_name(std::uint32_t level) { return std::string(kLevelPrefix) + std::to_string(level) + ": "; }

}  // namespace

CylinderHierarchy cylinder_hierarchy_gpu(Context& ctx, const CylinderMesh& mesh,
                                         const CylinderHierarchyOptions& options, const GpuRayCasterOptions& walk) {
    check_hierarchy_sizes(options.base, options.size);
    const std::uint32_t b = options.base, n = options.size;
    // Level 1 and the BVH every level casts through count as level 1's time.
    const auto start = std::chrono::steady_clock::now();
    GpuRayCaster caster(ctx, to_cylinder_frame(mesh), walk);
    const CylinderImage first = cylinder_raycast_gpu(caster, b, b);
    CylinderHierarchy h = detail::start_hierarchy(first, options);
    h.gpu_ms = caster.last_gpu_ms();
    h.level_ms.push_back(ms_since(start));
    if (n == b) return h;
    const auto later = std::chrono::steady_clock::now();
    Image bands = detail::upload_bands(ctx, h);
    Buffer directions = upload_buffer(ctx, detail::level_directions(b, n), "hierarchy directions");
    Graph g(ctx);
    const RaycastTree tree = import_raycast_tree(g, caster);
    detail::LevelBuffers lb{.bands = g.import_image(bands), .directions = g.import_buffer(directions)};
    const Spirv& kernel = tree.votes ? kCastLevel : kCastLevelPlain;
    detail::add_level_step(g, 0, b, n, b, lb, level_name(2) + "level 1's grid");
    std::uint32_t level = 2;
    for (std::uint32_t s = b; s < n; s *= 2, ++level) {
        detail::add_level_step(g, 1, s, n, b, lb, level_name(level) + "cells");
        const CastPush push{s, n, b, miss_code(options.miss), tree.scene, detail::kBehind, options.reach};
        g.add_compute_pass(
            level_name(level) + "rays",
            [&](PassBuilder& pb) {
                for (auto hnd : {tree.nodes, tree.corners, lb.grid, lb.cells}) pb.read(hnd, Access::ComputeRead);
                pb.read(tree.faces, Access::ComputeRead);
                pb.read(lb.directions, Access::ComputeRead);
                lb.bands = pb.write(lb.bands, Access::ComputeReadWrite);
            },
            [=, lv = lb](Cmd& c) {
                c.dispatch_threads(kernel, {s, s},
                                   {tree.nodes, tree.corners, tree.faces, lv.directions, lv.grid, lv.cells, lv.bands},
                                   push);
            });
        if (2 * s < n) detail::add_level_step(g, 2, s, n, b, lb, level_name(level) + "next grid");
    }
    g.export_image(lb.bands, Access::TransferSrc);
    Plan plan = g.compile();
    const bool timed = ctx.device_info().timestamp_period_ns > 0.0;
    plan.execute({.wait = true, .timestamps = timed});
    detail::download_bands(ctx, bands, h);

    // One submission: each later level's passes by their timestamps, and what else the submission
    // took (uploads, recording, waiting, downloads) counted in the last level.
    const double later_ms = ms_since(later);
    std::map<std::uint32_t, double> per_level;
    if (timed)
        for (const PassTiming& t : plan.timings())
            per_level[std::uint32_t(std::stoul(t.name.substr(kLevelPrefix.size())))] += t.gpu_ms;
    double passes_ms = 0.0;
    for (std::uint32_t l = 2; l < level; ++l) {
        h.level_ms.push_back(per_level[l]);
        passes_ms += per_level[l];
    }
    h.level_ms.back() += std::max(0.0, later_ms - passes_ms);
    if (timed) h.gpu_ms += plan.total_gpu_ms();
    return h;
}

}  // namespace gimg::passes

// The hierarchy's GPU encoder: level 1 by the GPU ray caster, then per level one pass over all its
// launches (shaders/cylinder_hierarchy/cast_launches.glsl: parity segment, direction and ray in
// one invocation, the CPU's rules and arithmetic), so it gives the CPU encoder's hierarchy bit for
// bit. Launch points and normals are computed on the host; one BVH serves level 1 and the rest.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/engine/upload.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/passes/raycast.h"

#include "cylinder_hierarchy/cast_launches_comp.h"
#include "cylinder_hierarchy/cast_launches_plain_comp.h"
#include "encode.h"
#include "ray_rules.h"

#include <chrono>
#include <cmath>

namespace gimg::passes {

namespace {

const Spirv kCastLaunches = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_cast_launches_comp);
const Spirv kCastLaunchesPlain = GIMG_SPIRV(gimg_spv_cylinder_hierarchy_cast_launches_plain_comp);

struct CastPush {
    std::uint32_t count;
    float scene;
    double behind;
};

// The valid launches' values (detail::CastLevel), in one pass; `gpu_ms` gains its GPU time.
std::vector<std::optional<double>> cast_level(Context& ctx, GpuRayCaster& caster,
                                              const std::vector<detail::Launch>& launches, double reach,
                                              double& gpu_ms) {
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < launches.size(); ++i)
        if (launches[i].valid) index.push_back(i);
    std::vector<std::optional<double>> t(launches.size());
    if (index.empty()) return t;
    // The shader's launch records (cast_launches.glsl), on both cores.
    std::vector<double> packed(8 * index.size());
    geo::parallel_for_chunks(index.size(), 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const detail::Launch& l = launches[index[k]];
            const double r = l.radial ? -1.0 : std::hypot(l.origin.x, l.origin.z);  // as parity_segment
            const double t_max = detail::launch_ray(l, true, reach).t_max;
            const double v[8] = {l.origin.x, l.origin.y, l.origin.z, r, l.normal.x, l.normal.y, l.normal.z, t_max};
            std::copy(v, v + 8, &packed[8 * k]);
        }
    });
    const auto count = std::uint32_t(index.size());
    Buffer records = upload_buffer(ctx, packed, "hierarchy launches");
    Buffer values = ctx.create_buffer({VkDeviceSize(count) * 8, "hierarchy values"});
    Buffer status = ctx.create_buffer({VkDeviceSize(count) * 4, "hierarchy status"});
    Graph g(ctx);
    const RaycastTree tree = import_raycast_tree(g, caster);
    const auto in = g.import_buffer(records);
    auto value_h = g.import_buffer(values), status_h = g.import_buffer(status);
    const CastPush push{count, tree.scene, detail::kBehind};
    const Spirv& kernel = tree.votes ? kCastLaunches : kCastLaunchesPlain;
    g.add_compute_pass(
        "hierarchy rays",
        [&](PassBuilder& b) {
            b.read(tree.nodes, Access::ComputeRead);
            b.read(tree.corners, Access::ComputeRead);
            for (auto h : {tree.faces, in}) b.read(h, Access::ComputeRead);
            value_h = b.write(value_h, Access::ComputeWrite);
            status_h = b.write(status_h, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kernel, {count}, {tree.nodes, tree.corners, tree.faces, in, value_h, status_h}, push);
        });
    g.export_buffer(value_h, Access::TransferSrc);
    g.export_buffer(status_h, Access::TransferSrc);
    Plan plan = g.compile();
    const bool timed = ctx.device_info().timestamp_period_ns > 0.0;
    plan.execute({.wait = true, .timestamps = timed});
    if (timed) gpu_ms += plan.total_gpu_ms();
    const std::vector<double> v = ctx.download<double>(values);
    const std::vector<std::uint32_t> st = ctx.download<std::uint32_t>(status);
    for (std::size_t k = 0; k < index.size(); ++k) {
        if (st[k] == 1) t[index[k]] = v[k];
        // More crossings than the walk keeps: the CPU casts it, by the same rules.
        if (st[k] == 2) t[index[k]] = detail::cast_launch(caster.bvh(), launches[index[k]], reach);
    }
    return t;
}

}  // namespace

CylinderHierarchy cylinder_hierarchy_gpu(Context& ctx, const CylinderMesh& mesh,
                                         const CylinderHierarchyOptions& options, const GpuRayCasterOptions& walk) {
    check_hierarchy_sizes(options.base, options.size);
    // Level 1 and the BVH every level casts through count as level 1's time.
    const auto start = std::chrono::steady_clock::now();
    GpuRayCaster caster(ctx, to_cylinder_frame(mesh), walk);
    const CylinderImage first = cylinder_raycast_gpu(caster, options.base, options.base);
    double gpu_ms = caster.last_gpu_ms();
    const double first_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    CylinderHierarchy h =
        detail::encode_hierarchy(first, first_ms, options, [&](const std::vector<detail::Launch>& launches) {
            return cast_level(ctx, caster, launches, options.reach, gpu_ms);
        });
    h.gpu_ms = gpu_ms;
    return h;
}

}  // namespace gimg::passes

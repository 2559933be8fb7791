// The hierarchy's GPU encoder: level 1 by the GPU ray caster, then per level two passes over all
// its launches, the parity segments and then the rays (GpuRayCaster, the CPU's arithmetic), so it
// gives the CPU encoder's hierarchy bit for bit. Launch points and normals are computed on the host;
// one BVH serves level 1 and the rest.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/passes/raycast.h"

#include "encode.h"
#include "ray_rules.h"

#include <chrono>

namespace gimg::passes {

CylinderHierarchy cylinder_hierarchy_gpu(Context& ctx, const CylinderMesh& mesh,
                                         const CylinderHierarchyOptions& options) {
    check_hierarchy_sizes(options.base, options.size);
    // Level 1 and the BVH every level casts through count as level 1's time.
    const auto start = std::chrono::steady_clock::now();
    GpuRayCaster caster(ctx, to_cylinder_frame(mesh));
    const CylinderImage first = cylinder_raycast_gpu(caster, options.base, options.base);
    double gpu_ms = caster.last_gpu_ms(), parity_ms = 0.0;
    const double first_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    CylinderHierarchy h =
        detail::encode_hierarchy(first, first_ms, options, [&](const std::vector<detail::Launch>& launches) {
            std::vector<std::size_t> index;
            std::vector<geo::Ray> segments;
            for (std::size_t i = 0; i < launches.size(); ++i)
                if (launches[i].valid) {
                    index.push_back(i);
                    segments.push_back(detail::parity_segment(launches[i].origin));
                }
            const std::vector<std::uint32_t> crossings = caster.crossings(segments);
            gpu_ms += caster.last_gpu_ms();
            parity_ms += caster.last_gpu_ms();
            std::vector<geo::Ray> rays(index.size());
            std::vector<std::uint8_t> inside(index.size());
            for (std::size_t k = 0; k < index.size(); ++k) {
                inside[k] = detail::inside_by_parity(crossings[k]);
                rays[k] = detail::launch_ray(launches[index[k]], inside[k], options.reach);
            }
            const std::vector<GpuRayHit> hits = caster.nearest(rays);
            gpu_ms += caster.last_gpu_ms();
            std::vector<std::optional<double>> t(launches.size());
            for (std::size_t k = 0; k < index.size(); ++k)
                if (hits[k].found()) t[index[k]] = inside[k] ? hits[k].t : -hits[k].t;
            return t;
        });
    h.gpu_ms = gpu_ms;
    h.gpu_parity_ms = parity_ms;
    return h;
}

}  // namespace gimg::passes

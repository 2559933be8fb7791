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
            // Radial launches need no parity: they fire from the wall, as level 1.
            std::vector<std::size_t> index, parity_index;
            std::vector<geo::Ray> segments;
            for (std::size_t i = 0; i < launches.size(); ++i)
                if (launches[i].valid) {
                    index.push_back(i);
                    if (launches[i].radial) continue;
                    parity_index.push_back(index.size() - 1);
                    segments.push_back(detail::parity_segment(launches[i].origin));
                }
            const std::vector<std::uint32_t> crossings = caster.crossings(segments);
            gpu_ms += caster.last_gpu_ms();
            parity_ms += caster.last_gpu_ms();
            std::vector<std::uint8_t> inside(index.size(), 0);
            for (std::size_t k = 0; k < parity_index.size(); ++k)
                inside[parity_index[k]] = detail::inside_by_parity(crossings[k]);
            // Two casts: the caster takes one face rule per call.
            std::vector<geo::Ray> rays[2];
            std::vector<std::size_t> which[2];
            for (std::size_t k = 0; k < index.size(); ++k) {
                const detail::Launch& l = launches[index[k]];
                rays[l.radial].push_back(l.radial ? detail::radial_ray(l)
                                                  : detail::launch_ray(l, inside[k], options.reach));
                which[l.radial].push_back(k);
            }
            std::vector<std::optional<double>> t(launches.size());
            for (int radial = 0; radial < 2; ++radial) {
                if (rays[radial].empty()) continue;
                const std::vector<GpuRayHit> hits = caster.nearest(rays[radial]);
                gpu_ms += caster.last_gpu_ms();
                for (std::size_t r = 0; r < hits.size(); ++r) {
                    if (!hits[r].found()) continue;
                    const std::size_t k = which[radial][r];
                    t[index[k]] = radial ? 1.0 + hits[r].t : (inside[k] ? hits[r].t : -hits[r].t);
                }
            }
            return t;
        });
    h.gpu_ms = gpu_ms;
    h.gpu_parity_ms = parity_ms;
    return h;
}

}  // namespace gimg::passes

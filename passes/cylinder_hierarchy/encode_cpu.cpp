// The hierarchy's CPU encoder: level 1 by the ordinary ray caster, every further level's rays
// through the BVH in double precision. Each level's grid is rebuilt from the stored float values,
// exactly as the decoder will, so encoder and decoder agree on every later launch.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/geometry/bvh.h"
#include "gimg/geometry/parallel_for.h"

#include "launch_rays.h"
#include "ray_rules.h"

#include "gimg/geometry/error.h"

#include <chrono>
#include <cmath>
#include <string>

namespace gimg::passes {

void check_hierarchy_sizes(std::uint32_t base, std::uint32_t size) {
    std::uint32_t s = base;
    while (s < size && s <= 16384) s *= 2;
    if (base < 2 || s != size || size > 16384)
        throw geo::InputError("hierarchy sizes: --size " + std::to_string(size) + " must be --base " +
                              std::to_string(base) + " times a power of 2 (base at least 2, size at most 16384)");
}

std::uint32_t CylinderHierarchy::levels() const {
    std::uint32_t l = 1;
    for (std::uint32_t s = base; s < size; s *= 2) ++l;
    return l;
}

CylinderHierarchy cylinder_hierarchy_cpu(const CylinderMesh& mesh, const CylinderHierarchyOptions& options) {
    check_hierarchy_sizes(options.base, options.size);
    const std::uint32_t b = options.base, n = options.size;
    CylinderHierarchy out;
    if (!(options.reach >= 0.0) || !std::isfinite(options.reach))
        throw geo::InputError("hierarchy reach must be a finite number >= 0 (0: without limit)");
    out.base = b;
    out.size = n;
    out.reach = options.reach;
    out.t.assign(std::size_t(n) * n, 0.0f);
    out.valid.assign(out.t.size(), 0);

    // Level 1: the ordinary image at B x B, stored as the distance from the wall.
    auto clock = std::chrono::steady_clock::now();
    auto lap = [&] {
        const auto now = std::chrono::steady_clock::now();
        out.level_ms.push_back(std::chrono::duration<double, std::milli>(now - clock).count());
        clock = now;
    };
    const CylinderImage first = cylinder_raycast(mesh, b, b);
    std::vector<float> t1(std::size_t(b) * b, 0.0f);
    for (std::size_t i = 0; i < t1.size(); ++i)
        if (first.covered[i]) t1[i] = float(1.0 - double(first.distance[i]));
    for (std::uint32_t v = 0; v < b; ++v)
        for (std::uint32_t u = 0; u < b; ++u) {
            out.t[std::size_t(v) * n + u] = t1[std::size_t(v) * b + u];
            out.valid[std::size_t(v) * n + u] = first.covered[std::size_t(v) * b + u];
        }
    HierarchyGrid grid = detail::level_one_grid(b, t1, first.covered);
    lap();

    const geo::TriangleBvh bvh(to_cylinder_frame(mesh));
    for (std::uint32_t s = b; s < n; s *= 2) {
        const detail::LevelLaunches launches = detail::level_launches(grid);
        const std::size_t count = std::size_t(s) * s;
        std::vector<float> th(count, 0.0f), tv(count, 0.0f), td(count, 0.0f);
        std::vector<std::uint8_t> hh(count, 0), hv(count, 0), hd(count, 0);
        geo::parallel_for_chunks(count, 256, [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                const std::pair<const std::vector<detail::Launch>*, std::pair<float*, std::uint8_t*>> bands[3] = {
                    {&launches.h, {&th[i], &hh[i]}}, {&launches.v, {&tv[i], &hv[i]}}, {&launches.d, {&td[i], &hd[i]}}};
                for (const auto& [band, result] : bands) {
                    const detail::Launch& l = (*band)[i];
                    if (!l.valid) continue;
                    if (const auto t = detail::cast_from(bvh, l, options.reach)) {
                        *result.first = float(*t);
                        *result.second = kHierarchyHit;
                    } else if (options.miss == HierarchyMiss::Surface) {
                        *result.first = 0.0f;
                        *result.second = kHierarchyMiss;
                    }
                }
            }
        });
        const detail::Bands bands{s};
        for (std::uint32_t v = 0; v < s; ++v)
            for (std::uint32_t u = 0; u < s; ++u) {
                const std::size_t i = std::size_t(v) * s + u;
                out.t[bands.h(u, v, n)] = th[i], out.valid[bands.h(u, v, n)] = hh[i];
                out.t[bands.v(u, v, n)] = tv[i], out.valid[bands.v(u, v, n)] = hv[i];
                out.t[bands.d(u, v, n)] = td[i], out.valid[bands.d(u, v, n)] = hd[i];
            }
        grid = detail::interleave(grid, launches, th, tv, td, hh, hv, hd);
        lap();
    }
    return out;
}

}  // namespace gimg::passes

// The hierarchy's CPU encoder (the GPU's is encode_gpu.cpp, the same arithmetic): level 1 from the
// ordinary image, every later level's rays through the BVH in double precision. Each level's grid
// is rebuilt from the stored float values, exactly as the decoder will, so encoder and decoder
// agree on every later launch.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/geometry/bvh.h"
#include "gimg/geometry/parallel_for.h"

#include "encode.h"
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

HierarchyMiss hierarchy_miss(const std::string& name) {
    if (name == "surface") return HierarchyMiss::Surface;
    if (name == "empty") return HierarchyMiss::Invalid;
    if (name == "radial") return HierarchyMiss::Radial;
    throw geo::InputError("hierarchy misses: \"" + name + "\" is not surface, empty or radial");
}

std::uint32_t CylinderHierarchy::levels() const {
    std::uint32_t l = 1;
    for (std::uint32_t s = base; s < size; s *= 2) ++l;
    return l;
}

namespace detail {

void check_reach(double reach) {
    if (!(reach >= 0.0) || !std::isfinite(reach))
        throw geo::InputError("hierarchy reach must be a finite number >= 0 (0: without limit)");
}

CylinderHierarchy empty_hierarchy(const CylinderHierarchyOptions& options) {
    check_reach(options.reach);
    CylinderHierarchy out;
    out.base = options.base;
    out.size = options.size;
    out.reach = options.reach;
    out.t.assign(std::size_t(options.size) * options.size, 0.0f);
    out.valid.assign(out.t.size(), kHierarchyEmpty);
    return out;
}

CylinderHierarchy start_hierarchy(const CylinderImage& first, const CylinderHierarchyOptions& options) {
    const std::uint32_t b = options.base, n = options.size;
    CylinderHierarchy out = empty_hierarchy(options);
    // Level 1: the ordinary image at B x B, stored as the distance from the wall.
    for (std::uint32_t v = 0; v < b; ++v)
        for (std::uint32_t u = 0; u < b; ++u) {
            const std::size_t i = std::size_t(v) * b + u, o = std::size_t(v) * n + u;
            out.valid[o] = first.covered[i];
            if (first.covered[i]) out.t[o] = float(1.0 - double(first.distance[i]));
        }
    return out;
}

CylinderHierarchy encode_hierarchy(const CylinderImage& first, double first_ms, const CylinderHierarchyOptions& options,
                                   const CastLevel& cast) {
    const std::uint32_t b = options.base, n = options.size;
    auto clock = std::chrono::steady_clock::now();
    CylinderHierarchy out = start_hierarchy(first, options);
    auto lap = [&] {
        const auto now = std::chrono::steady_clock::now();
        out.level_ms.push_back(std::chrono::duration<double, std::milli>(now - clock).count());
        clock = now;
    };
    std::vector<float> t1(std::size_t(b) * b);
    for (std::size_t i = 0; i < t1.size(); ++i) t1[i] = out.t[(i / b) * n + i % b];
    HierarchyGrid grid = level_one_grid(b, t1, first.covered);
    lap();
    out.level_ms.front() += first_ms;
    for (std::uint32_t s = b; s < n; s *= 2) {
        const LevelLaunches launches = level_launches(grid, b);
        const std::size_t count = std::size_t(s) * s;
        // One cast for the level: H, V and D one after another.
        std::vector<Launch> all;
        all.reserve(3 * count);
        for (const auto* band : {&launches.h, &launches.v, &launches.d})
            all.insert(all.end(), band->begin(), band->end());
        std::vector<std::optional<double>> t = cast(all);
        // A normal ray that found nothing, with HierarchyMiss::Radial: the radial ray at its sample.
        if (options.miss == HierarchyMiss::Radial) {
            const std::uint32_t next = 2 * s;
            std::vector<Launch> again;
            std::vector<std::size_t> where;
            for (std::size_t k = 0; k < all.size(); ++k) {
                if (!all[k].valid || all[k].radial || t[k]) continue;
                const std::size_t band = k / count, i = k % count;
                const std::uint32_t u = std::uint32_t(i % s), v = std::uint32_t(i / s);
                const std::uint32_t col = 2 * u + (band != 1), row = 2 * v + (band != 0);
                const Launch r = radial_launch(launches.directions[col], row_height(row, next, b));
                if (!r.valid) continue;
                again.push_back(r);
                where.push_back(k);
            }
            const std::vector<std::optional<double>> t2 = cast(again);
            for (std::size_t r = 0; r < where.size(); ++r) {
                all[where[r]] = again[r];
                t[where[r]] = t2[r];
            }
        }
        std::vector<float> values[3];
        std::vector<std::uint8_t> kinds[3];
        for (int k = 0; k < 3; ++k) {
            values[k].assign(count, 0.0f);
            kinds[k].assign(count, kHierarchyEmpty);
            for (std::size_t i = 0; i < count; ++i) {
                const Launch& l = all[k * count + i];
                if (!l.valid) continue;
                if (const auto& hit = t[k * count + i]) {
                    values[k][i] = float(*hit);
                    kinds[k][i] = l.radial ? kHierarchyRadial : kHierarchyHit;
                } else if (options.miss == HierarchyMiss::Surface && !l.radial) {
                    kinds[k][i] = kHierarchyMiss;
                }
            }
        }
        const Bands bands{s};
        for (std::uint32_t v = 0; v < s; ++v)
            for (std::uint32_t u = 0; u < s; ++u) {
                const std::size_t i = std::size_t(v) * s + u;
                out.t[bands.h(u, v, n)] = values[0][i], out.valid[bands.h(u, v, n)] = kinds[0][i];
                out.t[bands.v(u, v, n)] = values[1][i], out.valid[bands.v(u, v, n)] = kinds[1][i];
                out.t[bands.d(u, v, n)] = values[2][i], out.valid[bands.d(u, v, n)] = kinds[2][i];
            }
        grid = interleave(grid, launches, values[0], values[1], values[2], kinds[0], kinds[1], kinds[2]);
        lap();
    }
    return out;
}

}  // namespace detail

CylinderHierarchy cylinder_hierarchy_cpu(const CylinderMesh& mesh, const CylinderHierarchyOptions& options) {
    check_hierarchy_sizes(options.base, options.size);
    // Level 1 and the BVH the later levels cast through count as level 1's time.
    const auto start = std::chrono::steady_clock::now();
    const CylinderRaycaster caster(mesh);  // one BVH for level 1 and the rest
    const double tree_ms = detail::ms_since(start);
    const CylinderImage first = caster.project(options.base, options.base);
    const geo::TriangleBvh& bvh = caster.bvh();
    const double first_ms = detail::ms_since(start);
    CylinderHierarchy h =
        detail::encode_hierarchy(first, first_ms, options, [&](const std::vector<detail::Launch>& launches) {
            std::vector<std::optional<double>> t(launches.size());
            geo::parallel_for_chunks(launches.size(), 256, [&](std::size_t, std::size_t begin, std::size_t end) {
                for (std::size_t i = begin; i < end; ++i)
                    if (launches[i].valid) t[i] = detail::cast_launch(bvh, launches[i], options.reach);
            });
            return t;
        });
    h.tree_ms = tree_ms;
    return h;
}

}  // namespace gimg::passes

// Decoding a hierarchy: level 1 from its band, then every level's points from the recomputed
// launch points and outward normals (launch_rays.h) and the stored signed distances; and the
// decoded grid as a mesh.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/geometry/error.h"
#include "reconstruct/reconstruct_rules.h"

#include "launch_rays.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace gimg::passes {

namespace detail {

void check_decodable(const CylinderHierarchy& h, std::uint32_t level) {
    check_hierarchy_sizes(h.base, h.size);
    const std::size_t pixels = std::size_t(h.size) * h.size;
    if (h.t.size() != pixels || h.valid.size() != pixels)
        throw geo::InputError("hierarchy arrays do not match its " + std::to_string(h.size) + "x" +
                              std::to_string(h.size) + " size");
    if (level < 1 || level > h.levels())
        throw geo::InputError("hierarchy level " + std::to_string(level) + " of 1.." + std::to_string(h.levels()));
}

}  // namespace detail

HierarchyGrid decode_cylinder_hierarchy(const CylinderHierarchy& h, std::uint32_t level) {
    detail::check_decodable(h, level);
    const std::uint32_t b = h.base, n = h.size;
    std::vector<float> t1(std::size_t(b) * b);
    std::vector<std::uint8_t> v1(t1.size());
    for (std::uint32_t v = 0; v < b; ++v)
        for (std::uint32_t u = 0; u < b; ++u) {
            t1[std::size_t(v) * b + u] = h.t[std::size_t(v) * n + u];
            v1[std::size_t(v) * b + u] = h.valid[std::size_t(v) * n + u];
        }
    HierarchyGrid grid = detail::level_one_grid(b, t1, v1);
    for (std::uint32_t l = 2, s = b; l <= level; ++l, s *= 2) {
        const detail::LevelLaunches launches = detail::level_launches(grid, b);
        const std::size_t count = std::size_t(s) * s;
        std::vector<float> th(count), tv(count), td(count);
        std::vector<std::uint8_t> hh(count), hv(count), hd(count);
        const detail::Bands bands{s};
        for (std::uint32_t v = 0; v < s; ++v)
            for (std::uint32_t u = 0; u < s; ++u) {
                const std::size_t i = std::size_t(v) * s + u;
                th[i] = h.t[bands.h(u, v, n)], hh[i] = h.valid[bands.h(u, v, n)];
                tv[i] = h.t[bands.v(u, v, n)], hv[i] = h.valid[bands.v(u, v, n)];
                td[i] = h.t[bands.d(u, v, n)], hd[i] = h.valid[bands.d(u, v, n)];
            }
        grid = detail::interleave(grid, launches, th, tv, td, hh, hv, hd);
    }
    return grid;
}

double default_hierarchy_threshold(const HierarchyGrid& g) {
    std::vector<double> radius;
    for (std::size_t i = 0; i < g.points.size(); ++i)
        if (g.valid[i]) radius.push_back(std::hypot(g.points[i].x, g.points[i].z));
    if (radius.empty() || g.side == 0) return std::numeric_limits<double>::infinity();
    const auto mid = radius.begin() + std::ptrdiff_t(radius.size() / 2);
    std::nth_element(radius.begin(), mid, radius.end());
    const double pitch = std::max(2.0 * std::numbers::pi * *mid / double(g.side), 1.0 / double(g.side));
    return 12.0 * pitch;
}

geo::Mesh hierarchy_mesh(const HierarchyGrid& g, const CylinderFrame& frame, std::optional<double> threshold) {
    const double longest = threshold ? *threshold : default_hierarchy_threshold(g);
    const double longest_squared = longest * longest;
    geo::Mesh mesh;
    const std::uint32_t s = g.side;
    std::vector<std::uint32_t> vertex(g.points.size(), 0);
    for (std::size_t i = 0; i < g.points.size(); ++i) {
        if (!g.valid[i]) continue;
        vertex[i] = std::uint32_t(mesh.positions.size());
        mesh.positions.push_back(frame.to_model(g.points[i]));
    }
    auto squared = [&](std::size_t a, std::size_t b) {
        const glm::dvec3 d = g.points[a] - g.points[b];
        return glm::dot(d, d);
    };
    for (std::uint32_t v = 0; v < s; ++v) {
        if (!detail::rows_adjacent(v, s, g.base)) continue;
        const std::uint32_t v1 = (v + 1) % s;
        for (std::uint32_t u = 0; u < s; ++u) {
            const std::uint32_t u1 = (u + 1) % s;
            const std::size_t c[4] = {std::size_t(v) * s + u, std::size_t(v) * s + u1, std::size_t(v1) * s + u,
                                      std::size_t(v1) * s + u1};
            if (!(g.valid[c[0]] && g.valid[c[1]] && g.valid[c[2]] && g.valid[c[3]])) continue;
            if (std::max({squared(c[0], c[1]), squared(c[0], c[2]), squared(c[1], c[3]), squared(c[2], c[3])}) >
                longest_squared)
                continue;
            const bool faces_plus = g.outward[c[0]] + g.outward[c[1]] + g.outward[c[2]] + g.outward[c[3]] >= 0;
            const detail::BlockTriangles t =
                detail::block_triangles(squared(c[0], c[3]) <= squared(c[1], c[2]), faces_plus);
            for (const auto& tri : t.corner)
                mesh.triangles.push_back({vertex[c[tri[0]]], vertex[c[tri[1]]], vertex[c[tri[2]]]});
        }
    }
    detail::finish_mesh(mesh);
    return mesh;
}

}  // namespace gimg::passes

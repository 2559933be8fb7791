// Launch points and outward normals of a level (the thesis, 3.3.1; the spec's orientation rule:
// grid-order normals, which point away from the axis where the surface is seen directly, times the
// sign of the level-1 ancestors).
#include "launch_rays.h"

#include "gimg/geometry/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace gimg::passes::detail {

namespace {

// Adds the unit normal of triangle (a, b, c) unless it is degenerate.
void add_unit_normal(glm::dvec3& sum, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    if (len > 0.0 && std::isfinite(len)) sum += n / len;
}

// The outward unit normal from a sum of grid-order unit normals, or the radial direction where it
// vanishes.
glm::dvec3 oriented(const glm::dvec3& sum, const glm::dvec3& origin, int outward) {
    const double len = glm::length(sum);
    if (len > 1e-12) return double(outward) * sum / len;
    const double r = radius(origin);
    const glm::dvec3 radial = r > 0.0 ? glm::dvec3(origin.x / r, 0.0, origin.z / r) : glm::dvec3(1.0, 0.0, 0.0);
    return double(outward) * radial;
}

}  // namespace

double radius(const glm::dvec3& p) { return std::sqrt(p.x * p.x + p.z * p.z); }

double row_height(std::uint32_t j, std::uint32_t side, std::uint32_t base) {
    const double b = double(base ? base : side);
    const double y = 1.0 - (double(j) * (b / double(side)) + 0.5) / b;
    return y > 0.0 ? y : y + 1.0;
}

bool rows_adjacent(std::uint32_t v, std::uint32_t side, std::uint32_t base) {
    return row_height(v, side, base) > row_height((v + 1) % side, side, base);
}

HierarchyGrid level_one_grid(std::uint32_t base, const std::vector<float>& t, const std::vector<std::uint8_t>& valid) {
    HierarchyGrid g;
    g.side = base;
    g.base = base;
    g.points.assign(std::size_t(base) * base, glm::dvec3(0.0));
    g.valid = valid;
    g.outward.assign(g.points.size(), 1);
    const auto dirs = cylinder_directions(base);
    for (std::uint32_t v = 0; v < base; ++v) {
        const double y = row_height(v, base, base);
        for (std::uint32_t u = 0; u < base; ++u) {
            const std::size_t i = std::size_t(v) * base + u;
            if (!valid[i]) continue;
            const double d = 1.0 - double(t[i]);
            g.points[i] = {d * dirs[u][0], y, d * dirs[u][1]};
            g.outward[i] = d >= 0.0 ? 1 : -1;
        }
    }
    return g;
}

LevelLaunches level_launches(const HierarchyGrid& g, std::uint32_t base) {
    const std::uint32_t s = g.side;
    auto at = [&](std::uint32_t u, std::uint32_t v) { return std::size_t(v % s) * s + (u % s); };
    LevelLaunches out;
    out.h.resize(std::size_t(s) * s);
    out.v.resize(std::size_t(s) * s);
    out.d.resize(std::size_t(s) * s);
    std::vector<std::uint8_t> adjacent(s);
    for (std::uint32_t v = 0; v < s; ++v) adjacent[v] = rows_adjacent(v, s, base);
    // Cell centres first: the edge samples use them.
    for (std::uint32_t v = 0; v < s; ++v) {
        if (!adjacent[v]) continue;
        for (std::uint32_t u = 0; u < s; ++u) {
            const std::size_t a = at(u, v), b = at(u + 1, v), c = at(u, v + 1), d = at(u + 1, v + 1);
            Launch& l = out.d[at(u, v)];
            if (!(g.valid[a] && g.valid[b] && g.valid[c] && g.valid[d])) continue;
            l.valid = 1;
            l.origin = 0.25 * (g.points[a] + g.points[b] + g.points[c] + g.points[d]);
            l.span = std::max(glm::distance(g.points[a], g.points[d]), glm::distance(g.points[b], g.points[c]));
            l.outward = g.outward[a] + g.outward[b] + g.outward[c] + g.outward[d] >= 0 ? 1 : -1;
            // The ring (u, v + 1) -> (u, v) -> (u + 1, v) -> (u + 1, v + 1) around the centre: its
            // fan's normals point away from the axis where the grid sees the surface directly.
            glm::dvec3 sum(0.0);
            const glm::dvec3 ring[4] = {g.points[c], g.points[a], g.points[b], g.points[d]};
            for (int k = 0; k < 4; ++k) add_unit_normal(sum, l.origin, ring[k], ring[(k + 1) % 4]);
            l.normal = oriented(sum, l.origin, l.outward);
        }
    }
    for (std::uint32_t v = 0; v < s; ++v)
        for (std::uint32_t u = 0; u < s; ++u) {
            // Horizontal: between (u, v) and (u + 1, v); the cells below (row v) and above (row v - 1).
            const std::size_t a = at(u, v), b = at(u + 1, v);
            Launch& h = out.h[at(u, v)];
            if (g.valid[a] && g.valid[b]) {
                h.valid = 1;
                h.origin = 0.5 * (g.points[a] + g.points[b]);
                h.span = glm::distance(g.points[a], g.points[b]);
                h.outward = g.outward[a];
                glm::dvec3 sum(0.0);
                if (out.d[at(u, v)].valid) add_unit_normal(sum, g.points[a], g.points[b], out.d[at(u, v)].origin);
                if (out.d[at(u, v + s - 1)].valid)
                    add_unit_normal(sum, g.points[b], g.points[a], out.d[at(u, v + s - 1)].origin);
                h.normal = oriented(sum, h.origin, h.outward);
            }
            // Vertical: between (u, v) and (u, v + 1); the cells to the left (column u - 1) and right.
            if (!adjacent[v]) continue;
            const std::size_t c = at(u, v + 1);
            Launch& vl = out.v[at(u, v)];
            if (!(g.valid[a] && g.valid[c])) continue;
            vl.valid = 1;
            vl.origin = 0.5 * (g.points[a] + g.points[c]);
            vl.span = glm::distance(g.points[a], g.points[c]);
            vl.outward = g.outward[a];
            glm::dvec3 sum(0.0);
            const Launch& right = out.d[at(u, v)];
            const Launch& left = out.d[at(u + s - 1, v)];
            if (right.valid) add_unit_normal(sum, g.points[c], g.points[a], right.origin);
            if (left.valid) add_unit_normal(sum, g.points[a], g.points[c], left.origin);
            vl.normal = oriented(sum, vl.origin, vl.outward);
        }
    // The samples the rules above leave out, in the next grid of side 2S at (2u + 1, 2v), (2u,
    // 2v + 1) and (2u + 1, 2v + 1): radial rays.
    out.directions = radial_directions(2 * s, base);
    auto radial = [&](Launch& l, std::uint32_t i, std::uint32_t j) {
        if (!l.valid) l = radial_launch(out.directions[i], row_height(j, 2 * s, base));
    };
    for (std::uint32_t v = 0; v < s; ++v)
        for (std::uint32_t u = 0; u < s; ++u) {
            radial(out.h[at(u, v)], 2 * u + 1, 2 * v);
            radial(out.v[at(u, v)], 2 * u, 2 * v + 1);
            radial(out.d[at(u, v)], 2 * u + 1, 2 * v + 1);
        }
    return out;
}

std::vector<std::array<double, 2>> radial_directions(std::uint32_t side, std::uint32_t base) {
    std::vector<std::array<double, 2>> d(side);
    const double scale = double(base) / double(side);
    for (std::uint32_t i = 0; i < side; ++i) {
        const double theta = 2.0 * std::numbers::pi * (double(i) * scale + 0.5) / double(base);
        d[i] = {std::cos(theta), std::sin(theta)};
    }
    return d;
}

Launch radial_launch(const std::array<double, 2>& direction, double y) {
    Launch l;
    if (!(y > 0.0 && y < 1.0)) return l;
    l.valid = 1;
    l.radial = 1;
    l.origin = {direction[0], y, direction[1]};
    l.normal = {-direction[0], 0.0, -direction[1]};
    return l;
}

HierarchyGrid interleave(const HierarchyGrid& g, const LevelLaunches& l, const std::vector<float>& th,
                         const std::vector<float>& tv, const std::vector<float>& td,
                         const std::vector<std::uint8_t>& hit_h, const std::vector<std::uint8_t>& hit_v,
                         const std::vector<std::uint8_t>& hit_d) {
    const std::uint32_t s = g.side, n = 2 * s;
    HierarchyGrid out;
    out.side = n;
    out.base = g.base;
    out.points.assign(std::size_t(n) * n, glm::dvec3(0.0));
    out.valid.assign(out.points.size(), 0);
    out.outward.assign(out.points.size(), 1);
    const std::uint32_t base = g.base ? g.base : s;
    auto put = [&](std::uint32_t u, std::uint32_t v, const Launch& normal_launch, float t, std::uint8_t kind) {
        const std::size_t i = std::size_t(v) * n + u;
        if (kind == kHierarchyEmpty) return;
        const Launch launch =
            kind == kHierarchyRadial ? radial_launch(l.directions[u], row_height(v, n, base)) : normal_launch;
        // A radial launch carries only radial samples (as the GPU decoder reads any file).
        if (!launch.valid || (launch.radial && kind != kHierarchyRadial)) return;
        out.points[i] = launch.origin + double(t) * launch.normal;
        out.valid[i] = kind;
        out.outward[i] = launch.radial ? (t <= 1.0f ? 1 : -1) : launch.outward;
    };
    for (std::uint32_t v = 0; v < s; ++v)
        for (std::uint32_t u = 0; u < s; ++u) {
            const std::size_t i = std::size_t(v) * s + u;
            const std::size_t o = std::size_t(2 * v) * n + 2 * u;
            out.points[o] = g.points[i];
            out.valid[o] = g.valid[i];
            out.outward[o] = g.outward[i];
            put(2 * u + 1, 2 * v, l.h[i], th[i], hit_h[i]);
            put(2 * u, 2 * v + 1, l.v[i], tv[i], hit_v[i]);
            put(2 * u + 1, 2 * v + 1, l.d[i], td[i], hit_d[i]);
        }
    return out;
}

}  // namespace gimg::passes::detail

// z^a flattening of a one-ring and the Delaunay refill of its polygon (sec. 2.2.2).
#include "maps/ring_flattening.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gimg::passes {

namespace {

double cross2(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// d strictly inside the circumcircle of the counter-clockwise triangle (a, b, c).
bool in_circle(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
    const glm::dvec2 ad = a - d, bd = b - d, cd = c - d;
    const double det = (ad.x * ad.x + ad.y * ad.y) * cross2(bd, cd) - (bd.x * bd.x + bd.y * bd.y) * cross2(ad, cd) +
                       (cd.x * cd.x + cd.y * cd.y) * cross2(ad, bd);
    return det > 1e-14;
}

}  // namespace

bool gather_ring(const std::vector<glm::uvec3>& faces, const std::vector<std::uint32_t>& fs, std::uint32_t v, Ring& r) {
    r.ring.clear();
    r.faces.clear();
    if (fs.size() < 3) return false;
    // (v, a, b) rotated so that v comes first.
    auto after = [&](std::uint32_t f, std::uint32_t& a, std::uint32_t& b) {
        const glm::uvec3 t = faces[f];
        const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        a = t[(k + 1) % 3];
        b = t[(k + 2) % 3];
    };
    std::uint32_t first = 0, next = 0;
    after(fs[0], first, next);
    r.ring.push_back(first);
    r.faces.push_back(fs[0]);
    while (next != first) {
        if (r.ring.size() >= fs.size()) return false;
        bool found = false;
        for (std::uint32_t f : fs) {
            std::uint32_t a = 0, b = 0;
            after(f, a, b);
            if (a != next) continue;
            r.ring.push_back(next);
            r.faces.push_back(f);
            next = b;
            found = true;
            break;
        }
        if (!found) return false;
    }
    return r.ring.size() == fs.size();
}

double corner_angle(glm::dvec3 apex, glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 u = a - apex, w = b - apex;
    return std::atan2(glm::length(glm::cross(u, w)), glm::dot(u, w));
}

glm::dvec3 barycentric_2d(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    const double d = cross2(b - a, c - a);
    if (d == 0.0) return glm::dvec3(-1.0);  // a degenerate triangle holds no point
    const double u = cross2(b - p, c - p) / d, v = cross2(c - p, a - p) / d;
    return {u, v, 1.0 - u - v};
}

bool flatten_ring(const std::vector<glm::dvec3>& positions, std::uint32_t centre, Ring& r, bool polar,
                  double max_cone) {
    const std::size_t k = r.ring.size();
    if (k < 3) return false;
    const glm::dvec3 o = positions[centre];
    std::vector<double> angle(k), radius(k);
    double total = 0.0, longest = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
        angle[i] = corner_angle(o, positions[r.ring[i]], positions[r.ring[(i + 1) % k]]);
        radius[i] = glm::length(positions[r.ring[i]] - o);
        total += angle[i];
        longest = std::max(longest, radius[i]);
    }
    if (!(total > 0.0) || !(longest > 0.0)) return false;
    const double a = 2.0 * std::numbers::pi / total;
    if (max_cone > 0.0 && (a > max_cone || a * max_cone < 1.0)) return false;
    // z^a's sector angles; a sector it would open to pi or more (the old triangle would turn over
    // and the chart stop being one-to-one) is capped and the others share the excess.
    std::vector<double> sector(k);
    for (std::size_t i = 0; i < k; ++i) {
        if (!(angle[i] > 1e-12) || !(radius[i] > 0.0)) return false;
        sector[i] = a * angle[i];
    }
    constexpr double kCap = 0.9 * std::numbers::pi;
    std::vector<std::uint8_t> capped(k, 0);
    for (std::size_t round = 0; round < k; ++round) {
        double free = 0.0, fixed = 0.0;
        bool over = false;
        for (std::size_t i = 0; i < k; ++i) {
            if (!capped[i] && sector[i] > kCap) {
                capped[i] = 1;
                over = true;
            }
            if (capped[i])
                fixed += kCap;
            else
                free += sector[i];
        }
        if (!over) break;
        const double scale = (2.0 * std::numbers::pi - fixed) / free;
        for (std::size_t i = 0; i < k; ++i) sector[i] = capped[i] ? kCap : sector[i] * scale;
    }
    r.mu.resize(k);
    double theta = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
        if (!(sector[i] < std::numbers::pi - 1e-9)) return false;
        const double rho = std::pow(radius[i] / longest, polar ? 1.0 : a);
        r.mu[i] = {rho * std::cos(theta), rho * std::sin(theta)};
        theta += sector[i];
    }
    return true;
}

bool triangulate_ring(Ring& r, const std::vector<std::uint8_t>& forbidden) {
    const std::size_t k = r.ring.size();
    r.triangles.clear();
    std::vector<std::uint32_t> poly(k);
    for (std::uint32_t i = 0; i < k; ++i) poly[i] = i;
    const auto& mu = r.mu;
    while (poly.size() > 3) {
        bool cut = false;
        for (std::size_t i = 0; i < poly.size() && !cut; ++i) {
            const std::uint32_t a = poly[(i + poly.size() - 1) % poly.size()], b = poly[i],
                                c = poly[(i + 1) % poly.size()];
            if (!(cross2(mu[b] - mu[a], mu[c] - mu[a]) > 0.0)) continue;
            if (poly.size() > 3 && !forbidden.empty() && forbidden[a * k + c]) continue;
            bool empty = true;
            for (std::uint32_t q : poly) {
                if (q == a || q == b || q == c) continue;
                const glm::dvec3 w = barycentric_2d(mu[q], mu[a], mu[b], mu[c]);
                if (w.x >= 0.0 && w.y >= 0.0 && w.z >= 0.0) empty = false;
            }
            if (!empty) continue;
            r.triangles.push_back({a, b, c});
            poly.erase(poly.begin() + std::ptrdiff_t(i));
            cut = true;
        }
        if (!cut) return false;
    }
    if (!(cross2(mu[poly[1]] - mu[poly[0]], mu[poly[2]] - mu[poly[0]]) > 0.0)) return false;
    r.triangles.push_back({poly[0], poly[1], poly[2]});
    // Lawson flips: a diagonal shared by (a, b, c) and (b, a, d) flips to (c, d) when d lies in
    // the circumcircle of (a, b, c) and the quad is strictly convex. Terminates: each flip raises
    // the sorted angle vector.
    for (int sweep = 0; sweep < 64; ++sweep) {
        bool flipped = false;
        for (std::size_t s = 0; s < r.triangles.size(); ++s)
            for (std::size_t t = s + 1; t < r.triangles.size(); ++t)
                for (int e = 0; e < 3; ++e) {
                    const glm::uvec3 T = r.triangles[s], U = r.triangles[t];
                    const std::uint32_t a = T[e], b = T[(e + 1) % 3], c = T[(e + 2) % 3];
                    int f = -1;
                    for (int g = 0; g < 3; ++g)
                        if (U[g] == b && U[(g + 1) % 3] == a) f = g;
                    if (f < 0) continue;
                    const std::uint32_t d = U[(f + 2) % 3];
                    if (!in_circle(mu[a], mu[b], mu[c], mu[d])) continue;
                    if (!forbidden.empty() && forbidden[c * k + d]) continue;
                    // Convex quad a, d, b, c: both new triangles counter-clockwise.
                    if (!(cross2(mu[a] - mu[c], mu[d] - mu[c]) > 0.0) || !(cross2(mu[d] - mu[c], mu[b] - mu[c]) > 0.0))
                        continue;
                    r.triangles[s] = {c, a, d};
                    r.triangles[t] = {c, d, b};
                    flipped = true;
                    break;
                }
        if (!flipped) break;
    }
    return true;
}

Location locate(const Ring& r, glm::dvec2 p) {
    Location best;
    double best_min = -1e300;
    for (std::uint32_t t = 0; t < r.triangles.size(); ++t) {
        const glm::uvec3 T = r.triangles[t];
        const glm::dvec3 w = barycentric_2d(p, r.mu[T[0]], r.mu[T[1]], r.mu[T[2]]);
        const double m = std::min({w.x, w.y, w.z});
        if (m > best_min) {
            best_min = m;
            best = {t, w};
        }
    }
    glm::dvec3 w = glm::max(best.bary, glm::dvec3(0.0));
    const double sum = w.x + w.y + w.z;
    best.bary = sum > 0.0 ? w / sum : glm::dvec3(1.0 / 3.0);
    return best;
}

}  // namespace gimg::passes

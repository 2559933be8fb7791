// The accelerated start (sec. 3): graph distances s, t from the u = 0 and v = 0 sides stand for a
// flattening of the region, the bilinear normalisation of eq. (3) maps them onto the square, and a
// few sweeps of eq. (4) correct for sides that are not straight.
#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/passes/quad_region.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace gimg::passes {

namespace {

// Shortest edge-path lengths from every vertex marked as a source (a virtual source at distance 0).
std::vector<double> distances_from(const geo::Mesh& mesh, const geo::MeshAdjacency& adj,
                                   const std::vector<std::uint8_t>& source) {
    std::vector<double> d(mesh.vertex_count(), std::numeric_limits<double>::infinity());
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (std::uint32_t v = 0; v < d.size(); ++v)
        if (source[v]) d[v] = 0.0, queue.emplace(0.0, v);
    while (!queue.empty()) {
        const auto [dist, v] = queue.top();
        queue.pop();
        if (dist > d[v]) continue;
        for (std::uint32_t w : adj.neighbors(v)) {
            const double nd = dist + glm::distance(mesh.positions[v], mesh.positions[w]);
            if (nd < d[w]) d[w] = nd, queue.emplace(nd, w);
        }
    }
    return d;
}

// A piecewise-linear function through (x, y) points, sorted by x; clamped beyond the ends.
struct Polyline {
    std::vector<double> x, y;
    void add(double px, double py) { x.push_back(px), y.push_back(py); }
    void sort() {
        std::vector<std::size_t> order(x.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::sort(order.begin(), order.end(),
                  [&](std::size_t a, std::size_t b) { return x[a] < x[b] || (x[a] == x[b] && y[a] < y[b]); });
        std::vector<double> sx, sy;
        for (std::size_t i : order) sx.push_back(x[i]), sy.push_back(y[i]);
        x = std::move(sx), y = std::move(sy);
    }
    double operator()(double at) const {
        if (at <= x.front()) return y.front();
        if (at >= x.back()) return y.back();
        // The first point at or after `at`, by a branch-free binary search: the lookups of eq. (4)
        // land at random along the side, so branches mispredict half the time.
        const double* base = x.data();
        std::size_t len = x.size();
        while (len > 1) {
            const std::size_t half = len / 2;
            base = base[half] < at ? base + half : base;
            len -= half;
        }
        const std::size_t i = std::size_t(base - x.data()) + (*base < at);
        const double x0 = x[i - 1], x1 = x[i];
        return x1 > x0 ? y[i - 1] + (y[i] - y[i - 1]) * (at - x0) / (x1 - x0) : y[i];
    }
};

}  // namespace

glm::dvec2 bilinear_forward(glm::dvec2 uv, double s0, double t0, double s1, double t1) {
    return {(s0 + (s1 - s0) * uv.y) * uv.x, (t0 + (t1 - t0) * uv.x) * uv.y};
}

glm::dvec2 bilinear_inverse(glm::dvec2 st, double s0, double t0, double s1, double t1, bool* folded) {
    const double s = st.x, t = st.y, ds = s1 - s0, dt = t1 - t0;
    auto clamp01 = [](glm::dvec2 p) { return glm::clamp(p, glm::dvec2(0.0), glm::dvec2(1.0)); };
    auto u_of = [&](double v) { return s / (s0 + ds * v); };
    const double a = t0 * ds, b = t0 * s0 + dt * s - t * ds, c = -t * s0;
    const double disc = b * b - 4.0 * a * c;
    if (folded) *folded = false;
    if (disc < 0.0) return clamp01({s / s0, t / t0});  // inconsistent (s, t): the linear guess
    if (s1 / s0 + t1 / t0 > 1.0) {
        // The quadrilateral of corners is convex: the root continuous with the linear case (a -> 0).
        const double v = 2.0 * t * s0 / (b + std::sqrt(disc));
        return clamp01({u_of(v), v});
    }
    // The bilinear map folds: both roots may lie in the square; take the one nearest the linear guess.
    if (folded) *folded = true;
    const glm::dvec2 guess{s / s0, t / t0};
    glm::dvec2 best = clamp01(guess);
    double best_d = std::numeric_limits<double>::infinity();
    for (const double sign : {1.0, -1.0}) {
        const double v = a != 0.0 ? (-b + sign * std::sqrt(disc)) / (2.0 * a) : -c / b;
        const glm::dvec2 p{u_of(v), v};
        if (!(p.x >= 0.0 && p.x <= 1.0 && p.y >= 0.0 && p.y <= 1.0)) continue;
        if (glm::distance(p, guess) < best_d) best_d = glm::distance(p, guess), best = p;
    }
    return best;
}

std::array<std::vector<double>, 2> side_distances(const QuadRegion& region, const geo::MeshAdjacency& adj) {
    const std::size_t n = region.mesh.vertex_count();
    // Sides: 1 = W1 -> W2 (v = 0), 2 = W2 -> W3 (u = 1), 3 = W3 -> W4 (v = 1), 4 = W4 -> W1 (u = 0).
    std::vector<std::uint8_t> u0(n, 0), v0(n, 0);
    for (std::size_t i = 0; i < n; ++i) u0[i] = region.side[i] == 4, v0[i] = region.side[i] == 1;
    u0[region.corners[0]] = v0[region.corners[1]] = 1;  // each side's end corner belongs to the next side
    std::array<std::vector<double>, 2> st;              // the two searches are independent: one a core
    geo::parallel_for_chunks(2, 1, [&](std::size_t side, std::size_t, std::size_t) {
        st[side] = distances_from(region.mesh, adj, side ? v0 : u0);
    });
    return st;
}

std::size_t dijkstra_start(const QuadRegion& region, const geo::MeshAdjacency& adj,
                           const std::vector<glm::dvec2>& boundary_uv, double k, double tau,
                           std::vector<glm::dvec2>& uv, bool* folded) {
    const std::size_t n = region.mesh.vertex_count();
    const auto [s, t] = side_distances(region, adj);
    const double s0 = s[region.corners[1]], t0 = t[region.corners[3]];
    const double s1 = s[region.corners[2]], t1 = t[region.corners[2]];
    if (folded) *folded = !(s1 / s0 + t1 / t0 > 1.0);  // bilinear_inverse's test
    // S(v): s along the u = 1 side against v; T(u): t along the v = 1 side against u.
    Polyline big_s, big_t;
    for (std::size_t i = 0; i < n; ++i) {
        if (region.side[i] == 2 || i == region.corners[2]) big_s.add(boundary_uv[i].y, s[i]);
        if (region.side[i] == 3 || i == region.corners[3]) big_t.add(boundary_uv[i].x, t[i]);
    }
    big_s.sort();
    big_t.sort();
    uv = boundary_uv;
    for (std::size_t i = 0; i < n; ++i)
        if (region.side[i] == 0) uv[i] = bilinear_inverse({s[i], t[i]}, s0, t0, s1, t1);
    // Eq. (4): u <- k u + (1 - k) s / S(v), then v <- k v + (1 - k) t / T(u); at most 3 sweeps.
    // Each vertex reads only its own values: chunks of vertices on both cores.
    constexpr std::size_t kGrain = 1024;
    std::vector<double> chunk_worst(geo::chunk_count(n, kGrain));
    std::size_t sweeps = 0;
    while (sweeps < 3) {
        ++sweeps;
        geo::parallel_for_chunks(n, kGrain, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
            double worst = 0.0;
            for (std::size_t i = begin; i < end; ++i) {
                if (region.side[i] != 0) continue;
                const double su = std::clamp(s[i] / big_s(uv[i].y), 0.0, 1.0);
                worst = std::max(worst, std::abs(su - uv[i].x));
                uv[i].x = k * uv[i].x + (1.0 - k) * su;
                const double tv = std::clamp(t[i] / big_t(uv[i].x), 0.0, 1.0);
                worst = std::max(worst, std::abs(tv - uv[i].y));
                uv[i].y = k * uv[i].y + (1.0 - k) * tv;
            }
            chunk_worst[chunk] = worst;
        });
        if (*std::max_element(chunk_worst.begin(), chunk_worst.end()) < tau) break;
    }
    return sweeps;
}

}  // namespace gimg::passes

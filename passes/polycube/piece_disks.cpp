// The two sides of a slab piece as local meshes, cut open to disks along matching paths and their
// boundaries placed on the unit circle (used by the map, polycube_map.cpp).
#include "piece_disks.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

namespace gimg::passes::polycube {

namespace {

double wrap01(double x) { return x - std::floor(x); }

}  // namespace

// Normalised arc length from a common start, counter-clockwise seen from above, per point of a
// closed polyline: the start is where the line y = y_ref meets the loop at the largest x.
std::vector<double> loop_parameter(const std::vector<glm::dvec3>& p, double y_ref) {
    const std::size_t n = p.size();
    std::vector<glm::dvec2> q(n);
    for (std::size_t i = 0; i < n; ++i) q[i] = {p[i].x, p[i].y};
    const bool ccw = signed_area(q) >= 0.0;
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = ccw ? i : n - 1 - i;
    std::size_t seg = 0;
    double best = -1e300, t_best = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = q[order[i]], b = q[order[(i + 1) % n]];
        if ((a.y > y_ref) == (b.y > y_ref)) continue;
        const double t = (y_ref - a.y) / (b.y - a.y), x = a.x + t * (b.x - a.x);
        if (x > best) best = x, seg = i, t_best = t;
    }
    if (best == -1e300)  // the line misses the loop: start at the vertex of largest x
        for (std::size_t i = 0; i < n; ++i)
            if (q[order[i]].x > best) best = q[order[i]].x, seg = i, t_best = 0.0;
    std::vector<double> u(n, 0.0);
    const glm::dvec3 start = p[order[seg]] + t_best * (p[order[(seg + 1) % n]] - p[order[seg]]);
    double total = 0.0;
    glm::dvec3 prev = start;
    for (std::size_t k = 1; k <= n; ++k) {
        const std::size_t i = order[(seg + k) % n];
        total += glm::length(p[i] - prev);
        u[i] = total;
        prev = p[i];
    }
    total += glm::length(start - prev);
    for (double& x : u) x = wrap01(x / total);
    return u;
}

// The point of the closed polyline (with its parameters u) at parameter t.
glm::dvec3 point_at(const std::vector<glm::dvec3>& p, const std::vector<double>& u, double t) {
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        double du = u[j] - u[i];
        if (du < -0.5) du += 1.0;
        if (du > 0.5) du -= 1.0;
        if (du == 0.0) continue;
        double dt = t - u[i];
        if (du > 0 && dt < 0) dt += 1.0;
        if (du < 0 && dt > 0) dt -= 1.0;
        const double s = dt / du;
        if (s >= 0.0 && s <= 1.0) return p[i] + s * (p[j] - p[i]);
    }
    return p[0];
}

namespace {

// The boundary edge a -> b (in loop order) split at the point of parameter t.
std::uint32_t split_boundary_edge(Local& m, std::uint32_t a, std::uint32_t b, const glm::dvec3& q, double t) {
    const std::uint32_t id = std::uint32_t(m.pos.size());
    m.pos.push_back(q);
    m.global.push_back(kNone);
    m.origin.push_back(id);
    m.contour.push_back(m.contour[a]);
    m.u.push_back(t);
    for (std::size_t f = 0; f < m.tri.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (m.tri[f][k] == a && m.tri[f][(k + 1) % 3] == b) {
                const std::uint32_t c = m.tri[f][(k + 2) % 3];
                m.tri[f] = {a, id, c};
                m.tri.push_back({id, b, c});
                m.tri_source.push_back(m.tri_source[f]);
                return id;
            }
    throw geo::InputError("internal: a loop edge of a polycube piece was not found");
}

}  // namespace

void subdivide(Local& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const auto& t : m.tri)
        for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
        const auto key = std::minmax(a, b);
        const auto [it, added] = mid.emplace(key, std::uint32_t(m.pos.size()));
        if (!added) return it->second;
        m.pos.push_back(0.5 * (m.pos[a] + m.pos[b]));
        m.global.push_back(kNone);
        m.origin.push_back(it->second);
        // A loop edge's midpoint lies on the loop's polyline, halfway in its arc-length parameter.
        const bool on_loop = uses[key] == 1 && m.contour[a] >= 0 && m.contour[a] == m.contour[b];
        double u = 0.5 * (m.u[a] + m.u[b]);
        if (std::abs(m.u[a] - m.u[b]) > 0.5) u = std::fmod(u + 0.5, 1.0);
        m.contour.push_back(on_loop ? m.contour[a] : -1);
        m.u.push_back(on_loop ? u : 0.0);
        return it->second;
    };
    const std::size_t faces = m.tri.size();
    for (std::size_t f = 0; f < faces; ++f) {
        const glm::uvec3 t = m.tri[f];
        const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
        m.tri[f] = {ab, bc, ca};
        m.tri.push_back({t[0], ab, ca});
        m.tri.push_back({ab, t[1], bc});
        m.tri.push_back({ca, bc, t[2]});
        for (int k = 0; k < 3; ++k) m.tri_source.push_back(m.tri_source[f]);
    }
}

// The vertex at parameter t on the boundary loop `loop` (a vertex already there, or one added).
std::uint32_t vertex_at(Local& m, std::vector<std::uint32_t>& loop, double t, const std::vector<glm::dvec3>& curve,
                        const std::vector<double>& curve_u) {
    for (std::uint32_t v : loop) {
        const double d = std::abs(m.u[v] - t);
        if (std::min(d, 1.0 - d) < 1e-9) return v;
    }
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const std::uint32_t a = loop[i], b = loop[(i + 1) % loop.size()];
        double du = m.u[b] - m.u[a];
        if (du < -0.5) du += 1.0;
        if (du > 0.5) du -= 1.0;
        double dt = t - m.u[a];
        if (dt < -0.5) dt += 1.0;
        if (dt > 0.5) dt -= 1.0;
        if (du != 0.0 && dt / du > 0.0 && dt / du < 1.0) {
            const std::uint32_t id = split_boundary_edge(m, a, b, point_at(curve, curve_u, t), t);
            loop.insert(loop.begin() + std::ptrdiff_t(i + 1), id);  // a -> id -> b, the loop's start kept
            return id;
        }
    }
    throw geo::InputError("internal: a contour parameter was not found on a polycube loop");
}

std::vector<std::vector<std::uint32_t>> neighbours(const Local& m) {
    std::vector<std::vector<std::uint32_t>> nb(m.pos.size());
    for (const auto& t : m.tri)
        for (int k = 0; k < 3; ++k) nb[t[k]].push_back(t[(k + 1) % 3]), nb[t[(k + 1) % 3]].push_back(t[k]);
    for (auto& v : nb) {
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
    }
    return nb;
}

// Shortest path from any of `from` to a vertex with target[v], through vertices with free[v] only.
std::vector<std::uint32_t> shortest_path(const Local& m, const std::vector<std::vector<std::uint32_t>>& nb,
                                         const std::vector<std::uint32_t>& from,
                                         const std::vector<std::uint8_t>& target,
                                         const std::vector<std::uint8_t>& free) {
    std::vector<double> dist(m.pos.size(), 1e300);
    std::vector<std::uint32_t> prev(m.pos.size(), kNone);
    std::vector<std::uint8_t> source(m.pos.size(), 0);
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (std::uint32_t f : from) dist[f] = 0.0, source[f] = 1, queue.push({0.0, f});
    while (!queue.empty()) {
        const auto [d, v] = queue.top();
        queue.pop();
        if (d > dist[v]) continue;
        if (target[v] && !source[v]) {
            std::vector<std::uint32_t> path{v};
            while (prev[path.back()] != kNone) path.push_back(prev[path.back()]);
            std::reverse(path.begin(), path.end());
            return path;
        }
        if (!source[v] && !free[v]) continue;
        for (std::uint32_t w : nb[v]) {
            if (!free[w] && !target[w]) continue;
            const double nd = d + glm::length(m.pos[w] - m.pos[v]);
            if (nd < dist[w]) dist[w] = nd, prev[w] = v, queue.push({nd, w});
        }
    }
    return {};
}

// Every vertex on a cut gets one copy per wedge of triangles between cut or boundary edges.
void cut_open(Local& m, const std::set<std::pair<std::uint32_t, std::uint32_t>>& cut) {
    std::vector<std::vector<std::uint32_t>> faces_of(m.pos.size());
    for (std::uint32_t f = 0; f < m.tri.size(); ++f)
        for (int k = 0; k < 3; ++k) faces_of[m.tri[f][k]].push_back(f);
    std::set<std::uint32_t> on_cut;
    for (const auto& e : cut) on_cut.insert(e.first), on_cut.insert(e.second);
    for (std::uint32_t v : on_cut) {
        const auto& fs = faces_of[v];
        std::vector<std::uint32_t> group(fs.size());
        std::iota(group.begin(), group.end(), 0u);
        const auto find = [&](std::uint32_t a) {
            while (group[a] != a) a = group[a] = group[group[a]];
            return a;
        };
        for (std::size_t i = 0; i < fs.size(); ++i)
            for (std::size_t j = i + 1; j < fs.size(); ++j)
                for (int a = 0; a < 3; ++a) {
                    const std::uint32_t w = m.tri[fs[i]][a];
                    if (w == v) continue;
                    const bool shares = m.tri[fs[j]][0] == w || m.tri[fs[j]][1] == w || m.tri[fs[j]][2] == w;
                    if (shares && !cut.count(std::minmax(v, w))) group[find(std::uint32_t(i))] = find(std::uint32_t(j));
                }
        std::map<std::uint32_t, std::uint32_t> copy;
        for (std::size_t i = 0; i < fs.size(); ++i) {
            const std::uint32_t g = find(std::uint32_t(i));
            if (copy.empty()) copy[g] = v;
            if (!copy.count(g)) {
                copy[g] = std::uint32_t(m.pos.size());
                m.pos.push_back(m.pos[v]);
                m.global.push_back(m.global[v]);
                m.origin.push_back(m.origin[v]);
                m.contour.push_back(m.contour[v]);
                m.u.push_back(m.u[v]);
            }
            for (int k = 0; k < 3; ++k)
                if (m.tri[fs[i]][k] == v) m.tri[fs[i]][k] = copy[g];
        }
    }
}

// The single boundary loop of the cut piece, split where the edge kind changes, starting with the
// loop-0 run that leaves a copy of `start_landmark` (any run when there is no cut).
std::vector<Segment> disk_segments(const Local& m, const std::map<std::pair<std::uint32_t, std::uint32_t>, int>& cut_of,
                                   std::uint32_t start_landmark, int loop0_kind, bool& ok) {
    const auto loops = boundary_loops(m.tri);
    ok = loops.size() == 1;
    if (!ok) return {};
    const auto& b = loops[0];
    const std::size_t n = b.size();
    const auto kind = [&](std::size_t i) {
        const std::uint32_t x = m.origin[b[i % n]], y = m.origin[b[(i + 1) % n]];
        const auto it = cut_of.find(std::minmax(x, y));
        return it != cut_of.end() ? -(it->second + 1) : m.contour[b[i % n]] + 1;
    };
    std::size_t s = 0;
    if (!cut_of.empty()) {
        s = n;
        for (std::size_t i = 0; i < n; ++i)
            if (kind(i) == loop0_kind && m.origin[b[i]] == start_landmark && kind(i + n - 1) != loop0_kind) s = i;
        if (s == n) {
            ok = false;
            return {};
        }
    }
    std::vector<Segment> segs;
    for (std::size_t i = s; i < s + n; ++i) {
        const int k = kind(i);
        if (segs.empty() || segs.back().kind != k) segs.push_back({k, {b[i % n]}, 0.0});
        segs.back().vertices.push_back(b[(i + 1) % n]);
        segs.back().length += glm::length(m.pos[b[(i + 1) % n]] - m.pos[b[i % n]]);
    }
    return segs;
}

// Disk positions on the unit circle: each segment an arc of `span`, loop runs placed by their
// contour parameter, cuts by arc length.
void place_boundary(Local& m, const std::vector<Segment>& segs, const std::vector<double>& span) {
    double theta = 0.0;
    for (std::size_t s = 0; s < segs.size(); ++s) {
        const auto& v = segs[s].vertices;
        const bool whole = segs.size() == 1;
        std::vector<double> frac(v.size(), 0.0);
        if (segs[s].kind > 0) {
            const double u0 = m.u[v.front()], u1 = m.u[v.back()];
            double dir = 1.0;
            for (std::size_t i = 1; i < v.size(); ++i) {
                double d = m.u[v[i]] - u0;
                d -= std::round(d);
                if (d != 0.0) {
                    dir = d > 0 ? 1.0 : -1.0;
                    break;
                }
            }
            double total = wrap01(dir * (u1 - u0));
            if (total < 1e-12) total = 1.0;
            for (std::size_t i = 1; i + 1 < v.size(); ++i)
                frac[i] = std::min(wrap01(dir * (m.u[v[i]] - u0)) / total, 1.0);
            if (whole) {  // one loop, no cut: the parameter itself
                for (std::size_t i = 0; i < v.size(); ++i) frac[i] = m.u[v[i]];
            } else {
                frac.back() = 1.0;
            }
        } else {
            double run = 0.0;
            for (std::size_t i = 1; i < v.size(); ++i) {
                run += glm::length(m.pos[v[i]] - m.pos[v[i - 1]]);
                frac[i] = segs[s].length > 0 ? run / segs[s].length : double(i) / double(v.size() - 1);
            }
        }
        for (std::size_t i = 0; i + 1 < v.size(); ++i) {  // the last vertex starts the next segment
            const double a = whole ? kTwoPi * frac[i] : theta + span[s] * frac[i];
            m.disk[v[i]] = {std::cos(a), std::sin(a)};
        }
        theta += span[s];
    }
}

}  // namespace gimg::passes::polycube

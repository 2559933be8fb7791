// Closing the gaps of a plane section where it crosses a hole (Satoh & Imai sec. 3): the cubic
// Bezier between the extended end edges, else the fallback polyline, else the chord.
#include "polycube_parts.h"

#include <algorithm>
#include <cmath>

namespace gimg::passes {

namespace {

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

}  // namespace

std::optional<glm::dvec2> ray_intersection(glm::dvec2 p, glm::dvec2 d, glm::dvec2 q, glm::dvec2 e) {
    const double den = cross(d, e);
    const double scale = glm::length(d) * glm::length(e);
    if (!(std::abs(den) > 1e-12 * scale)) return std::nullopt;
    const double t = cross(q - p, e) / den, u = cross(q - p, d) / den;
    if (t < 0.0 || u < 0.0) return std::nullopt;
    return p + t * d;
}

std::vector<glm::dvec2> bezier_closure(glm::dvec2 r0, glm::dvec2 d0, glm::dvec2 r1, glm::dvec2 d1,
                                       std::uint32_t segments) {
    const auto m = ray_intersection(r0, d0, r1, d1);
    if (!m) return {};
    const glm::dvec2 m0 = 0.5 * (r0 + *m), m1 = 0.5 * (r1 + *m);
    segments = std::max<std::uint32_t>(segments, 1);
    std::vector<glm::dvec2> out;
    for (std::uint32_t i = 0; i <= segments; ++i) {
        const double t = double(i) / double(segments), s = 1.0 - t;
        out.push_back(s * s * s * r0 + 3.0 * s * s * t * m0 + 3.0 * s * t * t * m1 + t * t * t * r1);
    }
    out.front() = r0;
    out.back() = r1;
    return out;
}

std::vector<glm::dvec2> fallback_closure(glm::dvec2 r0, glm::dvec2 d0, glm::dvec2 r1, glm::dvec2 d1, std::uint32_t k) {
    k = std::max<std::uint32_t>(k, 1);
    const glm::dvec2 mr = 0.5 * (r0 + r1);
    const glm::dvec2 r[2] = {r0, r1};
    const glm::dvec2 d[2] = {glm::normalize(d0), glm::normalize(d1)};
    std::vector<glm::dvec2> half[2];
    for (int i = 0; i < 2; ++i)
        for (std::uint32_t j = 1; j <= k; ++j) {
            const glm::dvec2 q = r[i] + (double(j) / double(k)) * (mr - r[i]);
            const glm::dvec2 foot = r[i] + std::max(0.0, glm::dot(q - r[i], d[i])) * d[i];
            half[i].push_back(foot + (double(j) / double(k + 1)) * (q - foot));
        }
    std::vector<glm::dvec2> out{r0};
    out.insert(out.end(), half[0].begin(), half[0].end());
    out.insert(out.end(), half[1].rbegin(), half[1].rend());
    out.push_back(r1);
    return out;
}

namespace polycube {

double signed_area(const std::vector<glm::dvec2>& loop) {
    double a = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i) a += cross(loop[i], loop[(i + 1) % loop.size()]);
    return 0.5 * a;
}

double distance_to_loop(glm::dvec2 p, const std::vector<glm::dvec2>& loop) {
    double best = 1e300;
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const glm::dvec2 a = loop[i], ab = loop[(i + 1) % loop.size()] - a;
        const double len2 = glm::dot(ab, ab);
        const double t = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
        best = std::min(best, glm::length(p - (a + t * ab)));
    }
    return best;
}

bool point_in_loops(const std::vector<std::vector<glm::dvec2>>& loops, glm::dvec2 p) {
    bool inside = false;
    for (const auto& loop : loops)
        for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
            const glm::dvec2 a = loop[i], b = loop[j];
            if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) inside = !inside;
        }
    return inside;
}

bool segments_cross(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
    const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    const auto on = [](glm::dvec2 p, glm::dvec2 q, glm::dvec2 r, double side) {  // r on segment pq
        return side == 0.0 && std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
               r.y <= std::max(p.y, q.y);
    };
    return on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4);
}

namespace {

glm::dvec2 xy(const glm::dvec3& p) { return {p.x, p.y}; }

// True when the open polyline `curve` (its first and last points excepted) touches a segment.
bool crosses(const std::vector<glm::dvec2>& curve, const std::vector<std::pair<glm::dvec2, glm::dvec2>>& segments) {
    for (std::size_t i = 0; i + 1 < curve.size(); ++i) {
        glm::dvec2 a = curve[i], b = curve[i + 1];
        // Pull the ends in a little, so touching the chain at r0 and r1 is not a crossing.
        if (i == 0) a += 1e-6 * (b - a);
        if (i + 2 == curve.size()) b -= 1e-6 * (b - a);
        for (const auto& [c, d] : segments)
            if (segments_cross(a, b, c, d)) return true;
    }
    for (std::size_t i = 0; i + 2 < curve.size(); ++i)  // not itself either
        for (std::size_t j = i + 2; j + 1 < curve.size(); ++j)
            if (!(i == 0 && j + 2 == curve.size()) && segments_cross(curve[i], curve[i + 1], curve[j], curve[j + 1]))
                return true;
    return false;
}

}  // namespace

ClosureCounts close_contours(const geo::Mesh& mesh, std::vector<Contour>& contours, std::uint32_t k,
                             double sample_length) {
    ClosureCounts counts;
    std::size_t first = 0;
    while (first < contours.size()) {
        std::size_t last = first;
        while (last < contours.size() && contours[last].plane == contours[first].plane) ++last;
        // Every real segment of the plane, and the closing curves accepted so far: a new closure
        // must cross none of them.
        std::vector<std::pair<glm::dvec2, glm::dvec2>> blocked;
        for (std::size_t c = first; c < last; ++c) {
            const Contour& ct = contours[c];
            for (std::size_t i = 0; i < ct.vertices.size(); ++i)
                if (!ct.gap[i])
                    blocked.push_back({xy(mesh.positions[ct.vertices[i]]),
                                       xy(mesh.positions[ct.vertices[(i + 1) % ct.vertices.size()]])});
        }
        for (std::size_t c = first; c < last; ++c) {
            Contour& ct = contours[c];
            const std::size_t n = ct.vertices.size();
            const auto p = [&](std::size_t i) { return xy(mesh.positions[ct.vertices[i % n]]); };
            ct.closed.clear();
            const bool any_gap = std::find(ct.gap.begin(), ct.gap.end(), 1) != ct.gap.end();
            const bool all_gap = std::find(ct.gap.begin(), ct.gap.end(), 0) == ct.gap.end();
            if (!any_gap || all_gap) {  // a closed contour, or a section of a cap alone: as it is
                for (std::size_t i = 0; i < n; ++i) ct.closed.push_back(p(i));
                continue;
            }
            // Start at the beginning of a real run, then walk: real runs copied, gap runs closed.
            std::size_t s = 0;
            while (!(ct.gap[s] == 0 && ct.gap[(s + n - 1) % n] == 1)) ++s;
            std::size_t i = s;
            do {
                if (!ct.gap[i % n]) {
                    ct.closed.push_back(p(i));
                    ++i;
                    continue;
                }
                ++counts.chains;
                std::size_t j = i;  // the gap runs from vertex i (r0) to vertex j (r1)
                while (ct.gap[j % n]) ++j;
                const glm::dvec2 r0 = p(i), r1 = p(j);
                // The last non-degenerate edge of each chain, extended beyond its end.
                glm::dvec2 d0(0.0), d1(0.0);
                for (std::size_t b = 1; b < n && glm::length(d0) == 0.0; ++b) d0 = r0 - p(i + n - b);
                for (std::size_t b = 1; b < n && glm::length(d1) == 0.0; ++b) d1 = r1 - p(j + b);
                std::vector<glm::dvec2> curve;
                Closure method = Closure::Failed;
                if (glm::length(d0) > 0.0 && glm::length(d1) > 0.0) {
                    const auto m = ray_intersection(r0, d0, r1, d1);
                    // Rays meeting far beyond the gap (nearly parallel) would swing the curve far
                    // out of the section: the fallback's case too.
                    if (m && glm::length(*m - 0.5 * (r0 + r1)) <= 2.0 * glm::length(r1 - r0)) {
                        const double length = glm::length(*m - r0) + glm::length(r1 - *m);
                        const auto segments = std::uint32_t(std::clamp(length / sample_length, 4.0, 256.0));
                        curve = bezier_closure(r0, d0, r1, d1, segments);
                        if (!crosses(curve, blocked)) method = Closure::Bezier;
                    }
                    if (method == Closure::Failed) {
                        curve = fallback_closure(r0, d0, r1, d1, k);
                        if (!crosses(curve, blocked)) method = Closure::Fallback;
                    }
                }
                if (method == Closure::Failed) {
                    curve = {r0, r1};
                    if (!crosses(curve, blocked)) method = Closure::Chord;
                }
                if (method == Closure::Failed) {  // keep the cap's own section
                    curve.clear();
                    for (std::size_t g = i; g <= j; ++g) curve.push_back(p(g));
                }
                switch (method) {
                    case Closure::Bezier:
                        ++counts.bezier;
                        break;
                    case Closure::Fallback:
                        ++counts.fallback;
                        break;
                    case Closure::Chord:
                        ++counts.chord;
                        break;
                    case Closure::Failed:
                        ++counts.failed;
                        break;
                }
                for (std::size_t q = 0; q + 1 < curve.size(); ++q) {
                    ct.closed.push_back(curve[q]);
                    blocked.push_back({curve[q], curve[q + 1]});
                }
                i = j;
            } while (i < s + n);
        }
        first = last;
    }
    return counts;
}

}  // namespace polycube
}  // namespace gimg::passes

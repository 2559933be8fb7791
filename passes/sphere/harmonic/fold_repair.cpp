// Untangling a sphere map by moves into fan kernels (fold_repair.h).
#include "sphere/harmonic/fold_repair.h"

#include "sphere/sphere_steps.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>

namespace gimg::passes::detail {

namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

// Keeps the part of the convex polygon `poly` to the left of the directed line a -> b.
std::vector<glm::dvec2> clip_left_of(const std::vector<glm::dvec2>& poly, const glm::dvec2& a, const glm::dvec2& b) {
    std::vector<glm::dvec2> out;
    const glm::dvec2 dir = b - a;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2& p = poly[i];
        const glm::dvec2& q = poly[(i + 1) % poly.size()];
        const double sp = cross2(dir, p - a), sq = cross2(dir, q - a);
        if (sp >= 0.0) out.push_back(p);
        if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
    return out;
}

bool fan_counter_clockwise(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t v,
                           const glm::dvec3& p) {
    const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
    for (std::uint32_t k = 0; k < degree; ++k)
        if (!counter_clockwise(p, y[level.ring[begin + k]], y[level.ring[begin + (k + 1) % degree]])) return false;
    return true;
}

// Corners of flipped triangles (orientation <= 0, as map_stats_cpu counts them), and how many.
std::size_t flipped_corners(const RelaxationMesh& level, const std::vector<glm::dvec3>& y,
                            std::vector<std::uint8_t>& bad) {
    bad.assign(level.vertex_count(), 0);
    std::size_t flips = 0;
    for (std::uint32_t v = 0; v < level.vertex_count(); ++v) {
        const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
        for (std::uint32_t k = 0; k < degree; ++k) {
            const std::uint32_t a = level.ring[begin + k], b = level.ring[begin + (k + 1) % degree];
            if (v < a && v < b && !(orientation(y[v], y[a], y[b]) > 0.0)) {
                ++flips;
                bad[v] = bad[a] = bad[b] = 1;
            }
        }
    }
    return flips;
}

// Flipped triangles with a corner in `region` (marked in `in_region`), each counted once.
std::size_t flips_among_fans(const RelaxationMesh& level, const std::vector<glm::dvec3>& y,
                             const std::vector<std::uint32_t>& region, const std::vector<std::uint8_t>& in_region) {
    std::size_t flips = 0;
    for (std::uint32_t v : region) {
        const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
        for (std::uint32_t k = 0; k < degree; ++k) {
            const std::uint32_t a = level.ring[begin + k], b = level.ring[begin + (k + 1) % degree];
            const bool counted_here = (a > v || !in_region[a]) && (b > v || !in_region[b]);
            if (counted_here && !(orientation(y[v], y[a], y[b]) > 0.0)) ++flips;
        }
    }
    return flips;
}

// `region` grown by one ring.
void grow(const RelaxationMesh& level, std::vector<std::uint8_t>& region) {
    const std::vector<std::uint8_t> before = region;
    for (std::uint32_t v = 0; v < level.vertex_count(); ++v) {
        if (!before[v]) continue;
        for (std::uint32_t k = level.ring_offsets[v]; k < level.ring_offsets[v + 1]; ++k) region[level.ring[k]] = 1;
    }
}

// v's fan in the gnomonic projection about the centre of its link: a frame and the link's points.
struct GnomonicFan {
    glm::dvec3 c{0.0}, e1{0.0}, e2{0.0};  // e1 x e2 = c: the projection keeps orientation
    std::vector<glm::dvec2> link;
    glm::dvec2 lo{1e300}, hi{-1e300};  // the link's bounding box
    glm::dvec3 to_sphere(const glm::dvec2& x) const { return glm::normalize(c + x.x * e1 + x.y * e2); }
};

bool project_fan(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t v, GnomonicFan& fan) {
    const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
    if (degree < 3) return false;
    glm::dvec3 sum(0.0);
    for (std::uint32_t k = 0; k < degree; ++k) sum += y[level.ring[begin + k]];
    const double length = glm::length(sum);
    if (!(length > 1e-300)) return false;
    fan.c = sum / length;
    const glm::dmat3 frame = tangent_frame(fan.c);
    fan.e1 = frame[0];
    fan.e2 = frame[1];
    fan.link.resize(degree);
    for (std::uint32_t k = 0; k < degree; ++k) {
        const glm::dvec3& a = y[level.ring[begin + k]];
        const double height = glm::dot(a, fan.c);
        if (!(height > 1e-6)) return false;  // the fan does not fit one hemisphere around c
        // From differences to c, so that tiny fans keep their precision.
        const glm::dvec3 d = a - fan.c;
        fan.link[k] = glm::dvec2(glm::dot(d, fan.e1), glm::dot(d, fan.e2)) / height;
        fan.lo = glm::min(fan.lo, fan.link[k]);
        fan.hi = glm::max(fan.hi, fan.link[k]);
    }
    return fan.hi.x > fan.lo.x && fan.hi.y > fan.lo.y;
}

// The affine functions f_k(x) = distance of x to the left of link edge k (negative: to its right),
// and four that keep x near the link's bounding box: x in the kernel <=> min_k f_k(x) > 0.
struct Halfplane {
    glm::dvec2 normal;
    double offset;
    double at(const glm::dvec2& x) const { return glm::dot(normal, x) - offset; }
};

std::vector<Halfplane> fan_halfplanes(const GnomonicFan& fan) {
    std::vector<Halfplane> h;
    const std::size_t d = fan.link.size();
    for (std::size_t k = 0; k < d; ++k) {
        const glm::dvec2 a = fan.link[k], edge = fan.link[(k + 1) % d] - a;
        const double length = glm::length(edge);
        if (!(length > 0.0)) continue;
        const glm::dvec2 n = glm::dvec2(-edge.y, edge.x) / length;
        h.push_back({n, glm::dot(n, a)});
    }
    const glm::dvec2 margin = fan.hi - fan.lo;
    const glm::dvec2 lo = fan.lo - margin, hi = fan.hi + margin;
    h.push_back({{1.0, 0.0}, lo.x});
    h.push_back({{-1.0, 0.0}, -hi.x});
    h.push_back({{0.0, 1.0}, lo.y});
    h.push_back({{0.0, -1.0}, -hi.y});
    return h;
}

double min_value(const std::vector<Halfplane>& h, const glm::dvec2& x) {
    double m = 1e300;
    for (const Halfplane& f : h) m = std::min(m, f.at(x));
    return m;
}

// argmax_x min_k f_k(x) (a linear programme in x and t): at the optimum three of the functions are
// equal, so try every triple. Fans have 3-20 spokes; this runs on the few vertices around folds.
glm::dvec2 max_min_point(const std::vector<Halfplane>& h, double& best) {
    glm::dvec2 arg(0.0);
    best = -1e300;
    for (std::size_t i = 0; i < h.size(); ++i)
        for (std::size_t j = i + 1; j < h.size(); ++j)
            for (std::size_t k = j + 1; k < h.size(); ++k) {
                // n_i.x - b_i = n_j.x - b_j = n_k.x - b_k: two linear equations in x.
                const glm::dvec2 r1 = h[i].normal - h[j].normal, r2 = h[i].normal - h[k].normal;
                const double det = cross2(r1, r2);
                if (std::abs(det) < 1e-300) continue;
                const double s1 = h[i].offset - h[j].offset, s2 = h[i].offset - h[k].offset;
                const glm::dvec2 x((s1 * r2.y - s2 * r1.y) / det, (r1.x * s2 - r2.x * s1) / det);
                const double m = min_value(h, x);
                if (m > best) {
                    best = m;
                    arg = x;
                }
            }
    return arg;
}

// The centroid of the fan's kernel, in its gnomonic coordinates; false when the kernel is empty.
bool kernel_centroid(const GnomonicFan& fan, glm::dvec2& x) {
    const std::size_t degree = fan.link.size();
    // The kernel lies inside the link polygon, hence inside its bounding box.
    std::vector<glm::dvec2> kernel{fan.lo, {fan.hi.x, fan.lo.y}, fan.hi, {fan.lo.x, fan.hi.y}};
    for (std::size_t k = 0; k < degree && kernel.size() >= 3; ++k)
        kernel = clip_left_of(kernel, fan.link[k], fan.link[(k + 1) % degree]);
    if (kernel.size() < 3) return false;

    double area = 0.0;
    glm::dvec2 weighted(0.0);
    for (std::size_t i = 0; i < kernel.size(); ++i) {
        const glm::dvec2& p = kernel[i];
        const glm::dvec2& q = kernel[(i + 1) % kernel.size()];
        const double a = cross2(p - kernel[0], q - kernel[0]);
        area += a;
        weighted += a * (kernel[0] + p + q) / 3.0;
    }
    const glm::dvec2 extent = fan.hi - fan.lo;
    if (!(area > 1e-18 * extent.x * extent.y)) return false;
    x = weighted / area;
    return true;
}

// The least folded point of the fan (fan_least_folded_point), in its gnomonic coordinates; false
// when it is no better than `current` (v's point on the sphere).
bool least_folded(const GnomonicFan& fan, const glm::dvec3& current, glm::dvec2& x) {
    const std::vector<Halfplane> h = fan_halfplanes(fan);
    const glm::dvec3 d = current - fan.c;
    const double height = glm::dot(current, fan.c);
    const double now =
        height > 0.0 ? min_value(h, glm::dvec2(glm::dot(d, fan.e1), glm::dot(d, fan.e2)) / height) : -1e300;
    double best = 0.0;
    x = max_min_point(h, best);
    return best > now;
}

}  // namespace

bool fan_kernel_centroid(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t v,
                         glm::dvec3& centroid) {
    GnomonicFan fan;
    glm::dvec2 x;
    if (!project_fan(level, y, v, fan) || !kernel_centroid(fan, x)) return false;
    centroid = fan.to_sphere(x);
    return true;
}

bool fan_least_folded_point(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t v,
                            glm::dvec3& point) {
    GnomonicFan fan;
    glm::dvec2 x;
    if (!project_fan(level, y, v, fan) || !least_folded(fan, y[v], x)) return false;
    point = fan.to_sphere(x);
    return true;
}

FoldRepair repair_folds(const RelaxationMesh& level, std::vector<glm::dvec3>& y, const FoldRepairOptions& options) {
    FoldRepair result;
    std::vector<std::uint8_t> in_region;
    result.flips_before = result.flips_after = flipped_corners(level, y, in_region);
    const std::size_t move_budget = options.moves_per_vertex * level.vertex_count();
    for (std::size_t ring = 0; ring <= options.max_rings && result.flips_after > 0; ++ring) {
        result.rings = ring;
        for (std::size_t r = 0; r < ring; ++r) grow(level, in_region);
        std::vector<std::uint32_t> region;
        for (std::uint32_t v = 0; v < level.vertex_count(); ++v)
            if (in_region[v]) region.push_back(v);
        for (std::size_t sweep = 0; sweep < options.sweeps_per_round && result.flips_after > 0; ++sweep) {
            for (std::uint32_t v : region) {
                if (ring == 0 && fan_counter_clockwise(level, y, v, y[v])) continue;
                if (result.moves >= move_budget) {
                    result.flips_after = flipped_corners(level, y, in_region);
                    return result;
                }
                GnomonicFan fan;
                if (!project_fan(level, y, v, fan)) continue;
                // The centroid is in the kernel up to rounding; the test says so for sure. Where
                // the kernel is empty (the link itself is folded) the least folded point makes
                // room for the neighbours' moves.
                glm::dvec2 x;
                bool moved = kernel_centroid(fan, x) && fan_counter_clockwise(level, y, v, fan.to_sphere(x));
                if (!moved) moved = least_folded(fan, y[v], x);
                if (moved) {
                    y[v] = fan.to_sphere(x);
                    ++result.moves;
                }
            }
            // Moves only change the region's fans, and every fold has a corner in the region.
            result.flips_after = flips_among_fans(level, y, region, in_region);
        }
        flipped_corners(level, y, in_region);  // the next round grows around the folds that are left
    }
    return result;
}

}  // namespace gimg::passes::detail

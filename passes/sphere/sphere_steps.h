#pragma once
// Small steps on the unit sphere shared by the CPU spherical parameterizations: the orientation
// test, the kernel check, the per-vertex optimisation of Kanai's section 4.2 and the mass-centre
// normalisation.
//
// Precision: conformal maps of long limbs shrink them by factors of 1e6 and more, so triangles on
// the sphere get as small as 1e-7. Everything here is computed from differences of nearby points
// (which keep their relative precision) rather than from the points themselves (whose rounding,
// 1e-16, is then as large as the quantities wanted).

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace gimg::passes::detail {

// det(a, b, c) = 6 x the signed volume of (origin, a, b, c): > 0 when the triangle is
// counter-clockwise seen from outside the sphere. Written a.((b - a) x (c - a)) so that it keeps
// its sign for tiny triangles; sphere_metrics() counts flips with the same expression.
inline double orientation(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return glm::dot(a, glm::cross(b - a, c - a));
}

// A right-handed frame (e1, e2, n) around the unit vector n: projections onto e1, e2 seen from
// outside along n keep a triangle's orientation.
inline glm::dmat3 tangent_frame(const glm::dvec3& n) {
    const glm::dvec3 helper = std::abs(n.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 e1 = glm::normalize(glm::cross(helper, n));
    return glm::dmat3(e1, glm::cross(n, e1), n);
}

// Counter-clockwise with a margin: det > kKernelMargin |b - a| |c - a|. Computing det this way errs
// by a few 1e-16 |b - a| |c - a|, and a later step that moves every point (the Moebius recentring)
// rounds them again; the margin keeps an accepted triangle counter-clockwise through both, and is
// small enough not to stand in the way of the tiny triangles of long limbs.
inline constexpr double kKernelMargin = 1e-12;
inline bool counter_clockwise(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                              double margin = kKernelMargin) {
    const glm::dvec3 ab = b - a, ac = c - a;
    const double det = glm::dot(a, glm::cross(ab, ac));
    // det > margin |ab| |ac| without the square root (the margin is positive).
    return det > 0.0 && det * det > margin * margin * (glm::dot(ab, ab) * glm::dot(ac, ac));
}

// True when every face in `faces` (ids into `triangles`, each naming v) stays counter_clockwise()
// on the sphere with v moved to p, i.e. p lies in the kernel of v's one-ring (Kanai, fig. 5):
// moving a vertex within its kernel can never flip a triangle or fold the map.
bool in_kernel(std::span<const std::uint32_t> faces, const std::vector<glm::uvec3>& triangles,
               const std::vector<glm::dvec3>& y, std::uint32_t v, const glm::dvec3& p);

// One vertex's energy G(p) = sum_u w_u |y(u) - p|^2 over its neighbours, from sums taken once at
// the vertex's place o: with d = p - o, G(p) = G(o) - 2 d.L + W d.d, L = sum_u w_u (y(u) - o).
// A constant outside pull f (a Lagrange multiplier) adds -2 p.f: fold it into L.
struct VertexEnergy {
    glm::dvec3 origin{0.0};       // o
    glm::dvec3 laplacian{0.0};    // L (+ f)
    double weight_sum = 0.0;      // W = sum_u w_u
    double abs_weight_sum = 0.0;  // sum_u |w_u| (cotangent weights can be negative)
    double at_origin = 0.0;       // G(o)
    double at(const glm::dvec3& p) const {
        const glm::dvec3 d = p - origin;
        return at_origin - 2.0 * glm::dot(d, laplacian) + weight_sum * glm::dot(d, d);
    }
};

struct VertexStep {
    glm::dvec3 position{0.0};
    double energy_before = 0.0, energy_after = 0.0;
    std::size_t iterations = 0;
};

// Kanai's vertex Tutte / vertex conformal optimisation (4.2; which one depends on the weights in
// `e`), starting from e.origin: y' = normalize(y + c D_t y), D_t the tangential part of the
// Laplacian sum_u w_u (y(u) - y) / sum_u |w_u|, repeated until the vertex energy changes by less
// than `tolerance` (or max_iterations). The Laplacian is normalised by the weights so that c = 1
// moves the vertex to the weighted mean of its neighbours: the paper's step constants are 1.0 and
// "cannot exceed 1". Its fixed point is the vertex's minimiser on the sphere.
VertexStep optimise_vertex(const VertexEnergy& e, double step, double tolerance, std::size_t max_iterations);

// T_a(x) = (1 - |a|^2)(x - a) / |x - a|^2 - a, a Moebius transformation of the unit sphere
// (conformal) that moves the mass centre away from a; normalised against rounding.
inline glm::dvec3 moebius_move(const glm::dvec3& x, const glm::dvec3& a) {
    const glm::dvec3 d = x - a;
    return glm::normalize((1.0 - glm::dot(a, a)) * d / glm::dot(d, d) - a);
}

// Mean of the active points.
glm::dvec3 mass_centre(const std::vector<glm::dvec3>& y, std::span<const std::uint32_t> active);

// Moves the mass centre c (mean of the active y) towards the origin with the Moebius transformation
// of the sphere T_a(x) = (1 - |a|^2)(x - a) / |x - a|^2 - a, a = 3/4 c (to first order the a that
// zeroes the mean of evenly spread points). It is conformal, so unlike Gu's y = normalize(y - c) it
// adds no angle distortion. A triangle whose circumscribed cap holds the point T sends to infinity
// would flip, so a is halved until every face of `triangles` stays counter_clockwise() (up to 8
// times, then nothing is done). Returns |a| of the move made, 0 when none.
double normalise_mass_centre(std::vector<glm::dvec3>& y, std::span<const std::uint32_t> active,
                             const std::vector<glm::uvec3>& triangles);

// Every face counter_clockwise() (with the margin).
bool all_counter_clockwise(const std::vector<glm::uvec3>& triangles, const std::vector<glm::dvec3>& y);

// Faces of `triangles` that are not counter-clockwise on the sphere (sphere_metrics' flips).
std::size_t count_flips(const std::vector<glm::uvec3>& triangles, const std::vector<glm::dvec3>& y);

}  // namespace gimg::passes::detail

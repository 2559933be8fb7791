#pragma once
// The two stereographic charts of the unit sphere used by the `linear` spherical map.
//
// Both are chosen to preserve orientation: a triangle that is counter-clockwise in the plane is
// counter-clockwise seen from outside the sphere. The textbook projection (x, y) / (1 - z) with
// its inverse (2x, 2y, |w|^2 - 1) / (1 + |w|^2) mirrors; conjugating one coordinate fixes that, so
// no global reflection is needed at the end and flips mean what they say.
//
//   south chart: w = 0 is the south pole (0, 0, -1), w -> infinity the north pole.
//   north chart: q = 0 is the north pole (0, 0, 1),  q -> infinity the south pole.
//   On the overlap q = 1 / w, a Moebius map, so a map conformal in one chart is conformal in both.

#include <glm/vec3.hpp>

#include <complex>

namespace gimg::passes::linear_sphere {

using Complex = std::complex<double>;

inline glm::dvec3 sphere_from_south_chart(Complex w) {
    const double r2 = std::norm(w);
    return glm::dvec3(2.0 * w.real(), -2.0 * w.imag(), r2 - 1.0) / (1.0 + r2);
}

inline glm::dvec3 sphere_from_north_chart(Complex q) {
    const double r2 = std::norm(q);
    return glm::dvec3(2.0 * q.real(), 2.0 * q.imag(), 1.0 - r2) / (1.0 + r2);
}

// The inverse of sphere_from_south_chart; infinite at the north pole.
inline Complex south_chart_from_sphere(const glm::dvec3& p) { return Complex(p.x, -p.y) / (1.0 - p.z); }

// The same sphere point in the other chart (infinite at w = 0, the south pole).
inline Complex north_from_south_chart(Complex w) { return 1.0 / w; }

}  // namespace gimg::passes::linear_sphere

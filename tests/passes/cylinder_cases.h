#pragma once
// Analytic test cases for the cylindrical projections, each with its exact answer per pixel.

#include "gimg/geometry/mesh.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/cylinder.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <functional>
#include <numbers>
#include <optional>

namespace gimg::test {

inline passes::CylinderMesh to_cylinder_mesh(const geo::Mesh& m) {
    passes::CylinderMesh c;
    for (const auto& p : m.positions) c.positions.insert(c.positions.end(), {float(p.x), float(p.y), float(p.z)});
    for (const auto& t : m.triangles) c.triangles.insert(c.triangles.end(), {t.x, t.y, t.z});
    return c;
}

inline double theta_of(std::uint32_t u, std::uint32_t w) { return 2.0 * std::numbers::pi * (u + 0.5) / w; }
inline double y_of(std::uint32_t v, std::uint32_t h) { return 1.0 - (v + 0.5) / h; }

// The exact entry parameter of the line (t cos theta, y, t sin theta), walked from t = 1 down,
// into a convex box given by its centre, orthonormal axes and half sizes; nullopt if it misses or
// enters outside [-1, 1].
inline std::optional<double> box_entry(glm::dvec3 center, const glm::dvec3 axes[3], glm::dvec3 half, double theta,
                                       double y) {
    const glm::dvec3 origin{0.0, y, 0.0}, dir{std::cos(theta), 0.0, std::sin(theta)};
    double lo = -1e300, hi = 1e300;
    for (int k = 0; k < 3; ++k) {
        const double o = glm::dot(origin - center, axes[k]), d = glm::dot(dir, axes[k]);
        if (std::abs(d) < 1e-15) {
            if (std::abs(o) > half[k]) return std::nullopt;
            continue;
        }
        double t0 = (-half[k] - o) / d, t1 = (half[k] - o) / d;
        if (t0 > t1) std::swap(t0, t1);
        lo = std::max(lo, t0);
        hi = std::min(hi, t1);
    }
    if (lo > hi || hi < -1.0 || hi > 1.0) return std::nullopt;  // walking down from 1, we enter at hi
    return hi;
}

}  // namespace gimg::test

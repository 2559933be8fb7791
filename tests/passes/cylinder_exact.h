#pragma once
// The cylindrical-image definition of passes/cylinder.h evaluated literally, for shapes without a
// closed form: every pixel against every triangle. Slow (pixels x triangles), so for small cases.

#include "cylinder_cases.h"

#include "gimg/passes/cylinder.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace gimg::test {

inline glm::dvec3 apply(const passes::CylinderTransform& m, const float* p) {
    const double x = p[0], y = p[1], z = p[2];
    return {double(m[0]) * x + double(m[1]) * y + double(m[2]) * z + double(m[3]),
            double(m[4]) * x + double(m[5]) * y + double(m[6]) * z + double(m[7]),
            double(m[8]) * x + double(m[9]) * y + double(m[10]) * z + double(m[11])};
}

// The definition in cylinder.h evaluated literally: for every pixel and every triangle,
// Moller-Trumbore in double (no epsilon, edges inclusive) on the line from the wall through the
// axis, counting a crossing only where the triangle faces the wall the line starts from; the
// largest t in [-1, 1] wins. Depths in double, NaN where nothing is hit.
inline std::vector<double> brute_force(const passes::CylinderMesh& mesh, std::uint32_t w, std::uint32_t h,
                                       const passes::CylinderTransform& m = passes::kIdentityTransform) {
    const auto dirs = passes::cylinder_directions(w);
    std::vector<double> best(std::size_t(w) * h, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::dvec3 a = apply(m, &mesh.positions[3 * mesh.triangles[3 * f]]);
        const glm::dvec3 e1 = apply(m, &mesh.positions[3 * mesh.triangles[3 * f + 1]]) - a;
        const glm::dvec3 e2 = apply(m, &mesh.positions[3 * mesh.triangles[3 * f + 2]]) - a;
        const glm::dvec3 normal = glm::cross(e1, e2);
        for (std::uint32_t u = 0; u < w; ++u) {
            const glm::dvec3 dir{dirs[u][0], 0.0, dirs[u][1]};
            if (glm::dot(normal, dir) <= 0.0) continue;
            const glm::dvec3 pvec = glm::cross(dir, e2);
            const double inv = 1.0 / glm::dot(e1, pvec);
            for (std::uint32_t v = 0; v < h; ++v) {
                const glm::dvec3 tvec = glm::dvec3(0.0, y_of(v, h), 0.0) - a;
                const double bu = glm::dot(tvec, pvec) * inv;
                if (bu < 0.0 || bu > 1.0) continue;
                const glm::dvec3 qvec = glm::cross(tvec, e1);
                const double bv = glm::dot(dir, qvec) * inv;
                if (bv < 0.0 || bu + bv > 1.0) continue;
                const double t = glm::dot(e2, qvec) * inv;
                if (t < -1.0 || t > 1.0) continue;
                double& d = best[std::size_t(v) * w + u];
                if (!(d >= t)) d = t;
            }
        }
    }
    return best;
}

struct Agreement {
    std::size_t covered = 0;           // by the exact definition
    std::size_t coverage_differs = 0;  // covered by one and not the other
    std::size_t depth_differs = 0;     // covered by both, |delta d| > 1e-6
    double max_depth_error = 0.0;      // over the pixels both cover
};

inline Agreement compare(const passes::CylinderImage& got, const std::vector<double>& exact) {
    Agreement a;
    for (std::size_t i = 0; i < exact.size(); ++i) {
        const bool want = !std::isnan(exact[i]);
        a.covered += want;
        if (bool(got.covered[i]) != want) {
            ++a.coverage_differs;
            continue;
        }
        if (!want) continue;
        const double error = std::abs(double(got.distance[i]) - exact[i]);
        a.max_depth_error = std::max(a.max_depth_error, error);
        a.depth_differs += error > 1e-6;
    }
    return a;
}

inline passes::CylinderMesh soup(const std::vector<glm::dvec3>& corners) {
    passes::CylinderMesh m;
    for (const glm::dvec3& p : corners) m.positions.insert(m.positions.end(), {float(p.x), float(p.y), float(p.z)});
    for (std::uint32_t i = 0; i < corners.size(); ++i) m.triangles.push_back(i);
    return m;
}

}  // namespace gimg::test

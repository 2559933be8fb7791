#pragma once
// Rays a box test that rounds could lose, for the CPU BVH's and the GPU ray caster's tests: on a
// mesh of axis-aligned faces (whose boxes are flat), rays along and nearly along the axes
// (components of 1e-25, 1e-31, 1e-20) through every vertex, with directions from 1e-300 to 1e12
// long, and rays aimed at every vertex from 1e4 diagonals away.

#include "gimg/geometry/mesh.h"
#include "gimg/geometry/triangle_queries.h"

#include <vector>

namespace gimg::test {

inline std::vector<geo::Ray> flat_box_rays(const geo::Mesh& m, bool front_faces_only) {
    const double r = m.bounds().diagonal();
    const glm::dvec3 dirs[] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {1, 1e-25, 0}, {1e-31, -1, 1e-20}, {1, 1, 0}};
    std::vector<geo::Ray> rays;
    for (const glm::dvec3& p : m.positions)
        for (const glm::dvec3& dir : dirs)
            for (double scale : {1.0, 1e-12, 1e12, 1e-300}) {
                geo::Ray ray;
                ray.direction = scale * dir;
                ray.origin = p - 2.0 * r * dir;
                ray.t_max = 4.0 * r / scale;
                ray.front_faces_only = front_faces_only;
                rays.push_back(ray);
                ray.origin = p + 1e4 * r * glm::dvec3(0.6, -0.8, 0.0);
                ray.direction = scale * (p - ray.origin);
                ray.t_max = 2.0 / scale;
                rays.push_back(ray);
            }
    return rays;
}

}  // namespace gimg::test

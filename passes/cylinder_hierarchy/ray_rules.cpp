#include "ray_rules.h"

#include <cmath>

namespace gimg::passes::detail {

geo::Ray parity_segment(const glm::dvec3& origin) {
    const double r = radius(origin);
    const glm::dvec3 wall = r > 0.0 ? glm::dvec3(origin.x / r, origin.y, origin.z / r) : glm::dvec3(1.0, origin.y, 0.0);
    geo::Ray segment;
    segment.origin = wall;
    segment.direction = origin - wall;
    segment.t_min = 0.0;
    segment.t_max = 1.0;
    return segment;
}

geo::Ray launch_ray(const Launch& l, bool inside, double reach) {
    geo::Ray ray;
    ray.origin = l.origin;
    ray.direction = inside ? l.normal : -l.normal;
    ray.t_min = -kBehind;
    if (reach > 0.0) ray.t_max = reach * l.span;
    return ray;
}

geo::Ray radial_ray(const Launch& l) {
    geo::Ray ray;
    ray.origin = {0.0, l.origin.y, 0.0};
    ray.direction = l.normal;
    ray.t_min = -1.0;
    ray.t_max = 1.0;
    ray.front_faces_only = true;
    return ray;
}

std::optional<double> cast_launch(const geo::TriangleBvh& bvh, const Launch& l, double reach) {
    if (l.radial) {
        if (const auto hit = bvh.intersect_nearest(radial_ray(l))) return 1.0 + hit->t;
        return std::nullopt;
    }
    const bool inside = inside_by_parity(bvh.crossings(parity_segment(l.origin)));
    if (const auto hit = bvh.intersect_nearest(launch_ray(l, inside, reach))) return inside ? hit->t : -hit->t;
    return std::nullopt;
}

}  // namespace gimg::passes::detail

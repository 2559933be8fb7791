#include "ray_rules.h"

#include <cmath>

namespace gimg::passes::detail {

bool launch_inside(const geo::TriangleBvh& bvh, const glm::dvec3& origin) {
    const double r = std::hypot(origin.x, origin.z);
    const glm::dvec3 wall = r > 0.0 ? glm::dvec3(origin.x / r, origin.y, origin.z / r) : glm::dvec3(1.0, origin.y, 0.0);
    geo::Ray segment;
    segment.origin = wall;
    segment.direction = origin - wall;
    segment.t_min = 0.0;
    segment.t_max = 1.0;
    const std::vector<geo::RayHit> hits = bvh.intersect_all(segment);
    std::size_t crossings = 0;
    double last = -1.0;
    for (const geo::RayHit& h : hits) {
        if (crossings == 0 || h.t - last > kSameHit) ++crossings;
        last = h.t;
    }
    return crossings % 2 == 1;
}

std::optional<double> cast_from(const geo::TriangleBvh& bvh, const Launch& l, double reach) {
    const bool inside = launch_inside(bvh, l.origin);
    geo::Ray ray;
    ray.origin = l.origin;
    ray.direction = inside ? l.normal : -l.normal;
    ray.t_min = -kBehind;
    if (reach > 0.0) ray.t_max = reach * l.span;
    const auto hit = bvh.intersect_nearest(ray);
    if (!hit) return std::nullopt;
    return inside ? hit->t : -hit->t;
}

}  // namespace gimg::passes::detail

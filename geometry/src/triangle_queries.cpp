#include "gimg/geometry/triangle_queries.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace gimg::geo {

namespace {

// Closest point on segment [a, b] to p, as the parameter s in [0, 1] (0 for a zero-length segment).
double closest_on_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    if (!(len2 > 0.0)) return 0.0;
    return std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0);
}

TrianglePoint closest_on_edges(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 corner[3] = {a, b, c};
    TrianglePoint best;
    best.distance_squared = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const glm::dvec3 &u = corner[k], &v = corner[(k + 1) % 3];
        const double s = closest_on_segment(p, u, v);
        const glm::dvec3 q = u + s * (v - u);
        const double d2 = glm::dot(p - q, p - q);
        if (d2 < best.distance_squared) {
            best.point = q;
            best.distance_squared = d2;
            best.barycentric = glm::dvec3(0.0);
            best.barycentric[k] = 1.0 - s;
            best.barycentric[(k + 1) % 3] = s;
        }
    }
    return best;
}

TrianglePoint make(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& w) {
    return {q, w, glm::dot(p - q, p - q)};
}

}  // namespace

TrianglePoint closest_point_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                        const glm::dvec3& c) {
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return make(p, a, {1, 0, 0});  // corner a

    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return make(p, b, {0, 1, 0});  // corner b

    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {  // edge ab
        const double denom = d1 - d3;
        if (denom > 0.0) {
            const double v = d1 / denom;
            return make(p, a + v * ab, {1.0 - v, v, 0.0});
        }
        return closest_on_edges(p, a, b, c);
    }

    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return make(p, c, {0, 0, 1});  // corner c

    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {  // edge ac
        const double denom = d2 - d6;
        if (denom > 0.0) {
            const double w = d2 / denom;
            return make(p, a + w * ac, {1.0 - w, 0.0, w});
        }
        return closest_on_edges(p, a, b, c);
    }

    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {  // edge bc
        const double denom = (d4 - d3) + (d5 - d6);
        if (denom > 0.0) {
            const double w = (d4 - d3) / denom;
            return make(p, b + w * (c - b), {0.0, 1.0 - w, w});
        }
        return closest_on_edges(p, a, b, c);
    }

    // Inside the face region. va + vb + vc is |ab x ac|^2 > 0 for a proper triangle; a degenerate
    // one (or round-off on a sliver) lands on the edges instead of dividing by ~0.
    const double sum = va + vb + vc;
    if (!(sum > 0.0)) return closest_on_edges(p, a, b, c);
    const double v = vb / sum, w = vc / sum;
    return make(p, a + ab * v + ac * w, {1.0 - v - w, v, w});
}

bool intersect_ray_triangle(const Ray& ray, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                            TriangleHit& hit) {
    const glm::dvec3 e1 = b - a, e2 = c - a;
    if (ray.front_faces_only && !(glm::dot(glm::cross(e1, e2), ray.direction) < 0.0)) return false;
    const glm::dvec3 pvec = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, pvec);
    if (det == 0.0) return false;
    const double inv = 1.0 / det;
    const glm::dvec3 tvec = ray.origin - a;
    const double u = glm::dot(tvec, pvec) * inv;
    if (!(u >= 0.0 && u <= 1.0)) return false;
    const glm::dvec3 qvec = glm::cross(tvec, e1);
    const double v = glm::dot(ray.direction, qvec) * inv;
    if (!(v >= 0.0 && u + v <= 1.0)) return false;
    const double t = glm::dot(e2, qvec) * inv;
    if (!(t >= ray.t_min && t <= ray.t_max)) return false;
    hit.t = t;
    hit.barycentric = glm::dvec3(1.0 - u - v, u, v);
    return true;
}

}  // namespace gimg::geo

#pragma once
// Exact point-triangle and ray-triangle queries in double precision: the primitives under the BVH
// (and what its brute-force tests compare against).

#include <glm/vec3.hpp>

#include <limits>

namespace gimg::geo {

struct TrianglePoint {
    glm::dvec3 point{0.0};
    // Weights of corners (a, b, c): point = w.x a + w.y b + w.z c, each in [0, 1], sum 1.
    glm::dvec3 barycentric{1.0, 0.0, 0.0};
    double distance_squared = 0.0;
};

// Closest point of triangle (a, b, c) to p, by Voronoi regions of the corners, edges and face
// (Ericson, Real-Time Collision Detection 5.1.5). Degenerate triangles (collinear or coincident
// corners) fall back to the closest of the three edges, so the result is always finite.
TrianglePoint closest_point_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                        const glm::dvec3& c);

struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, 1.0};  // need not be unit length; t is in its units
    double t_min = 0.0;
    double t_max = std::numeric_limits<double>::infinity();
    // Only triangles facing the ray's origin: dot(cross(b - a, c - a), direction) < 0.
    bool front_faces_only = false;
};

struct TriangleHit {
    double t = 0.0;
    // Weights of corners (a, b, c) at the hit point.
    glm::dvec3 barycentric{1.0, 0.0, 0.0};
};

// Moeller-Trumbore, both faces hit unless ray.front_faces_only, edges and corners included (closed test on the
// barycentrics), t in the closed range [ray.t_min, ray.t_max]. A ray in the triangle's plane
// (determinant exactly 0) never hits. Returns false on a miss.
bool intersect_ray_triangle(const Ray& ray, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                            TriangleHit& hit);

}  // namespace gimg::geo

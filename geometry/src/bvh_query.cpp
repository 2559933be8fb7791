// Closest-point and ray traversals of TriangleBvh. Each keeps the best answer as the pair
// (distance or t, face index) and only prunes boxes strictly worse than it, so the answer is the
// lexicographic minimum over all faces whatever order the nodes are visited in.
#include "gimg/geometry/bvh.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace gimg::geo {

namespace {

// No tree is deeper than about 96 (see bvh_build.cpp); a traversal holds at most depth + 1 entries.
constexpr int kStackSize = 128;

double box_distance_squared(const BvhNode& node, const glm::dvec3& p) {
    const glm::dvec3 d =
        glm::max(glm::max(glm::dvec3(node.bounds_min) - p, p - glm::dvec3(node.bounds_max)), glm::dvec3(0.0));
    return glm::dot(d, d);
}

// The box test, in float and conservative, so that no rounding can cull a triangle the exact
// triangle test would hit: every box is widened by w, 2^-18 (64 float epsilons) of the largest
// coordinate in play (the tree's extent() or the origin's), far beyond the rounding of the origin, the box
// and the slab distances to float. Distances are measured in units of the direction's largest
// component, so no inverse overflows; an axis whose component is at most 1e-30 of it counts as
// parallel (along it the ray moves less than w inside any box it can reach). The GPU ray caster
// (shaders/raycast/walk.glsl) computes the same values.
struct RaySlabs {
    glm::vec3 origin, inv;
    bool parallel[3];
    float w;
    double scale;  // the direction's largest component (double: a direction of 1e-300 still hits)
    RaySlabs(const Ray& ray, float extent) : origin(ray.origin) {
        const glm::dvec3& d = ray.direction;
        const double m = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
        scale = m;
        for (int a = 0; a < 3; ++a) {
            parallel[a] = std::abs(d[a]) <= 1e-30 * m;
            inv[a] = parallel[a] ? 0.0f : float(m / d[a]);
        }
        w = 0x1p-18f * (extent + std::max({std::abs(origin.x), std::abs(origin.y), std::abs(origin.z)}));
    }
    // A lower bound of the distance at which the ray enters the node's box within [t_near, t_far],
    // or +inf on a miss (always for a zero direction, which hits nothing).
    double enter(const BvhNode& node, double t_near, double t_far) const {
        constexpr double kMiss = std::numeric_limits<double>::infinity();
        if (!(scale > 0.0)) return kMiss;
        const float a = float(t_near * scale), b = float(t_far * scale);
        float tn = a - 2.4e-7f * std::abs(a), tf = b + 2.4e-7f * std::abs(b);
        for (int k = 0; k < 3; ++k) {
            const float lo = node.bounds_min[k] - w, hi = node.bounds_max[k] + w;
            if (parallel[k]) {
                if (origin[k] < lo || origin[k] > hi) return kMiss;
                continue;
            }
            const float t0 = (lo - origin[k]) * inv[k], t1 = (hi - origin[k]) * inv[k];
            tn = std::max(tn, std::min(t0, t1));
            tf = std::min(tf, std::max(t0, t1));
        }
        return tn <= tf ? double(tn) / scale : kMiss;
    }
};

}  // namespace

ClosestPointResult TriangleBvh::closest_point(const glm::dvec3& p, double max_distance, std::uint32_t hint_face) const {
    ClosestPointResult best;
    if (nodes_.empty() || !(max_distance >= 0.0)) return best;
    double best_d2 = max_distance * max_distance;
    auto consider = [&](std::uint32_t slot) {
        const Triangle& t = triangles_[slot];
        const TrianglePoint tp = closest_point_on_triangle(p, t.a, t.b, t.c);
        const std::uint32_t face = face_order_[slot];
        if (tp.distance_squared < best_d2 || (tp.distance_squared == best_d2 && face < best.face)) {
            best_d2 = tp.distance_squared;
            best.face = face;
            best.point = tp.point;
            best.barycentric = tp.barycentric;
        }
    };
    if (hint_face < slot_of_face_.size()) consider(slot_of_face_[hint_face]);

    struct Entry {
        std::uint32_t node;
        double d2;
    };
    Entry stack[kStackSize];
    int top = 0;
    Entry e{0, box_distance_squared(nodes_[0], p)};
    for (;;) {
        if (e.d2 <= best_d2) {
            const BvhNode& node = nodes_[e.node];
            if (!node.is_leaf()) {
                const std::uint32_t l = node.first, r = node.first + 1;
                const double dl = box_distance_squared(nodes_[l], p), dr = box_distance_squared(nodes_[r], p);
                // The nearer child next, so that it tightens best_d2 first; the farther one waits.
                const Entry near_e = dl <= dr ? Entry{l, dl} : Entry{r, dr};
                const Entry far_e = dl <= dr ? Entry{r, dr} : Entry{l, dl};
                if (far_e.d2 <= best_d2) stack[top++] = far_e;
                e = near_e;
                continue;
            }
            for (std::uint32_t s = node.first; s < node.first + node.count; ++s) consider(s);
        }
        if (top == 0) break;
        e = stack[--top];
    }
    if (best.found()) best.distance = std::sqrt(best_d2);
    return best;
}

std::optional<RayHit> TriangleBvh::intersect_nearest(const Ray& ray) const {
    if (nodes_.empty()) return std::nullopt;
    const RaySlabs slabs(ray, extent());
    RayHit best;
    best.t = ray.t_max;
    struct Entry {
        std::uint32_t node;
        double t;
    };
    Entry stack[kStackSize];
    int top = 0;
    const double t_root = slabs.enter(nodes_[0], ray.t_min, ray.t_max);
    if (t_root == std::numeric_limits<double>::infinity()) return std::nullopt;
    Entry e{0, t_root};
    for (;;) {
        if (e.t <= best.t) {
            const BvhNode& node = nodes_[e.node];
            if (!node.is_leaf()) {
                const std::uint32_t l = node.first, r = node.first + 1;
                const double tl = slabs.enter(nodes_[l], ray.t_min, best.t);
                const double tr = slabs.enter(nodes_[r], ray.t_min, best.t);
                // The nearer child next; the farther one waits.
                const Entry near_e = tl <= tr ? Entry{l, tl} : Entry{r, tr};
                const Entry far_e = tl <= tr ? Entry{r, tr} : Entry{l, tl};
                if (far_e.t != std::numeric_limits<double>::infinity()) stack[top++] = far_e;
                if (near_e.t != std::numeric_limits<double>::infinity()) {
                    e = near_e;
                    continue;
                }
            } else {
                for (std::uint32_t s = node.first; s < node.first + node.count; ++s) {
                    const Triangle& t = triangles_[s];
                    Ray clipped = ray;
                    clipped.t_max = best.t;  // ties at best.t are still found (closed range)
                    TriangleHit h;
                    if (!intersect_ray_triangle(clipped, t.a, t.b, t.c, h)) continue;
                    const std::uint32_t face = face_order_[s];
                    if (h.t < best.t || (h.t == best.t && face < best.face)) {
                        best.t = h.t;
                        best.face = face;
                        best.barycentric = h.barycentric;
                    }
                }
            }
        }
        if (top == 0) break;
        e = stack[--top];
    }
    if (best.face == kInvalidIndex) return std::nullopt;
    return best;
}

namespace {

// Visits every face whose box the ray enters in [t_min, t_max]; `visit(slot, hit)` returns false
// to stop.
template <class Visit>
void for_each_hit(const BvhNodeArray& nodes, float extent, const Ray& ray, Visit&& visit) {
    if (nodes.empty()) return;
    const RaySlabs slabs(ray, extent);
    std::uint32_t stack[kStackSize];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const BvhNode& node = nodes[stack[--top]];
        if (slabs.enter(node, ray.t_min, ray.t_max) == std::numeric_limits<double>::infinity()) continue;
        if (node.is_leaf()) {
            for (std::uint32_t s = node.first; s < node.first + node.count; ++s)
                if (!visit(s)) return;
            continue;
        }
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
    }
}

}  // namespace

bool TriangleBvh::intersect_any(const Ray& ray) const {
    bool found = false;
    for_each_hit(nodes_, extent(), ray, [&](std::uint32_t s) {
        const Triangle& t = triangles_[s];
        TriangleHit h;
        found = intersect_ray_triangle(ray, t.a, t.b, t.c, h);
        return !found;
    });
    return found;
}

std::vector<RayHit> TriangleBvh::intersect_all(const Ray& ray) const {
    std::vector<RayHit> hits;
    auto test = [&](std::uint32_t s) {
        const Triangle& t = triangles_[s];
        TriangleHit h;
        if (!intersect_ray_triangle(ray, t.a, t.b, t.c, h)) return false;
        hits.push_back({h.t, face_order_[s], h.barycentric});
        return true;
    };
    for_each_hit(nodes_, extent(), ray, [&](std::uint32_t s) {
        test(s);
        if (!copy_slots_.empty())
            if (const auto c = copy_slots_.find(face_order_[s]); c != copy_slots_.end())
                for (std::uint32_t copy : c->second) test(copy);
        return true;
    });
    std::sort(hits.begin(), hits.end(),
              [](const RayHit& x, const RayHit& y) { return x.t != y.t ? x.t < y.t : x.face < y.face; });
    return hits;
}

std::uint32_t TriangleBvh::crossings(const Ray& ray) const {
    const std::vector<RayHit> hits = intersect_all(ray);
    std::uint32_t n = 0;
    for (std::size_t k = 0; k < hits.size(); ++k)
        if (k == 0 || hits[k].t - hits[k - 1].t > 1e-12) ++n;
    return n;
}

}  // namespace gimg::geo

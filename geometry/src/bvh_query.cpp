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

// Slab test against the node's box for t in [t_near, t_far]; returns the entry t or +inf on a
// miss. The interval is widened by a relative 1e-12 so that rounding in the slab arithmetic can
// never cull a triangle lying on the box's face (the triangle test itself is exact).
struct RaySlabs {
    glm::dvec3 origin, inv_dir;
    bool axis_parallel[3];
    explicit RaySlabs(const Ray& ray) : origin(ray.origin) {
        for (int a = 0; a < 3; ++a) {
            axis_parallel[a] = ray.direction[a] == 0.0;
            inv_dir[a] = axis_parallel[a] ? 0.0 : 1.0 / ray.direction[a];
        }
    }
    double enter(const BvhNode& node, double t_near, double t_far) const {
        t_near -= 1e-12 * std::abs(t_near);
        t_far += 1e-12 * std::abs(t_far);
        for (int a = 0; a < 3; ++a) {
            if (axis_parallel[a]) {
                if (origin[a] < double(node.bounds_min[a]) || origin[a] > double(node.bounds_max[a]))
                    return std::numeric_limits<double>::infinity();
                continue;
            }
            double t0 = (double(node.bounds_min[a]) - origin[a]) * inv_dir[a];
            double t1 = (double(node.bounds_max[a]) - origin[a]) * inv_dir[a];
            if (t0 > t1) std::swap(t0, t1);
            t0 -= 1e-12 * std::abs(t0);
            t1 += 1e-12 * std::abs(t1);
            t_near = std::max(t_near, t0);
            t_far = std::min(t_far, t1);
            if (t_near > t_far) return std::numeric_limits<double>::infinity();
        }
        return t_near;
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
    stack[top++] = {0, box_distance_squared(nodes_[0], p)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 > best_d2) continue;
        const BvhNode& node = nodes_[e.node];
        if (node.is_leaf()) {
            for (std::uint32_t s = node.first; s < node.first + node.count; ++s) consider(s);
            continue;
        }
        const std::uint32_t l = node.first, r = node.first + 1;
        const double dl = box_distance_squared(nodes_[l], p), dr = box_distance_squared(nodes_[r], p);
        // Push the farther child first so the nearer one is searched first and tightens best_d2.
        const Entry near_e = dl <= dr ? Entry{l, dl} : Entry{r, dr};
        const Entry far_e = dl <= dr ? Entry{r, dr} : Entry{l, dl};
        if (far_e.d2 <= best_d2) stack[top++] = far_e;
        if (near_e.d2 <= best_d2) stack[top++] = near_e;
    }
    if (best.found()) best.distance = std::sqrt(best_d2);
    return best;
}

std::optional<RayHit> TriangleBvh::intersect_nearest(const Ray& ray) const {
    if (nodes_.empty()) return std::nullopt;
    const RaySlabs slabs(ray);
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
    stack[top++] = {0, t_root};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.t > best.t) continue;
        const BvhNode& node = nodes_[e.node];
        if (node.is_leaf()) {
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
            continue;
        }
        const std::uint32_t l = node.first, r = node.first + 1;
        const double tl = slabs.enter(nodes_[l], ray.t_min, best.t);
        const double tr = slabs.enter(nodes_[r], ray.t_min, best.t);
        const Entry near_e = tl <= tr ? Entry{l, tl} : Entry{r, tr};
        const Entry far_e = tl <= tr ? Entry{r, tr} : Entry{l, tl};
        if (far_e.t != std::numeric_limits<double>::infinity()) stack[top++] = far_e;
        if (near_e.t != std::numeric_limits<double>::infinity()) stack[top++] = near_e;
    }
    if (best.face == kInvalidIndex) return std::nullopt;
    return best;
}

namespace {

// Visits every face whose box the ray enters in [t_min, t_max]; `visit(slot, hit)` returns false
// to stop.
template <class Visit>
void for_each_hit(const BvhNodeArray& nodes, const Ray& ray, Visit&& visit) {
    if (nodes.empty()) return;
    const RaySlabs slabs(ray);
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
    for_each_hit(nodes_, ray, [&](std::uint32_t s) {
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
    for_each_hit(nodes_, ray, [&](std::uint32_t s) {
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

// Vertex splits on the sphere with placement and the kernel-checked vertex Tutte optimisation.
#include "sphere/hierarchy/split_refinement.h"

#include "sphere/sphere_steps.h"

#include <algorithm>
#include <cmath>

namespace gimg::passes::detail {

namespace {

constexpr int kPlacementHalvings = 60;
constexpr int kTowardsTargetHalvings = 8;
constexpr double kTutteTolerance = 1e-14;  // vertex Tutte energy change that ends a vertex's iterations
constexpr std::size_t kTutteIterations = 100;

// Uniform-weight vertex energy from the faces around v: each neighbour of a closed manifold mesh is
// in two of them, so half of the two other corners per face sums every neighbour once.
VertexEnergy tutte_energy(const geo::ProgressiveReplay& replay, const std::vector<glm::dvec3>& y, std::uint32_t v) {
    VertexEnergy e;
    e.origin = y[v];
    for (std::uint32_t f : replay.faces_of(v)) {
        const glm::uvec3 t = replay.triangles()[f];
        for (int k = 0; k < 3; ++k) {
            if (t[k] == v) continue;
            const glm::dvec3 d = y[t[k]] - y[v];
            e.laplacian += 0.5 * d;
            e.at_origin += 0.5 * glm::dot(d, d);
        }
        e.weight_sum += 1.0;
    }
    e.abs_weight_sum = e.weight_sum;
    return e;
}

// Vertex Tutte optimisation (eq. 10) with the kernel check; false when refused.
bool relax(const geo::ProgressiveReplay& replay, std::vector<glm::dvec3>& y, std::uint32_t v) {
    const VertexStep step = optimise_vertex(tutte_energy(replay, y, v), 1.0, kTutteTolerance, kTutteIterations);
    if (!in_kernel(replay.faces_of(v), replay.triangles(), y, v, step.position)) return false;
    y[v] = step.position;
    return true;
}

// Gradient of the orientation of face f with respect to v's position: det(v, a, b) = v.(a x b).
glm::dvec3 orientation_gradient(const glm::uvec3& t, const std::vector<glm::dvec3>& y, std::uint32_t v) {
    for (int k = 0; k < 3; ++k)
        if (t[k] == v) return glm::cross(y[t[(k + 1) % 3]], y[t[(k + 2) % 3]]);
    return glm::dvec3(0.0);
}

// Just off the parent, inside the wedge the two recreated faces need (see split_refinement.h).
bool place_next_to_parent(const geo::ProgressiveReplay& replay, std::vector<glm::dvec3>& y, const geo::VertexSplit& s) {
    const glm::dvec3 origin = y[s.parent];
    glm::dvec3 d(0.0);
    for (int i = 0; i < 2; ++i) {
        glm::dvec3 n = orientation_gradient(s.born_triangles[i], y, s.vertex);
        n -= glm::dot(n, origin) * origin;
        const double length = glm::length(n);
        if (length > 0.0) d += n / length;
    }
    if (!(glm::length(d) > 1e-12)) return false;
    d = glm::normalize(d);
    double nearest = 2.0;
    for (std::uint32_t f : replay.faces_of(s.vertex)) {
        const glm::uvec3 t = replay.triangles()[f];
        for (int k = 0; k < 3; ++k)
            if (t[k] != s.vertex && t[k] != s.parent) nearest = std::min(nearest, glm::length(y[t[k]] - origin));
    }
    double eps = 0.25 * nearest;
    for (int i = 0; i < kPlacementHalvings; ++i, eps *= 0.5) {
        const glm::dvec3 p = glm::normalize(origin + eps * d);
        if (in_kernel(replay.faces_of(s.vertex), replay.triangles(), y, s.vertex, p)) {
            y[s.vertex] = p;
            return true;
        }
    }
    return false;
}

// Fallback when the wedge direction finds no room (the parent nearly in line with left and right,
// or slivers already in the fan): points inside each face the new vertex takes over from its
// parent, ever closer to the parent. Any point of the open wedge those faces make near the parent
// serves, so trying one per face catches what a single direction misses.
bool place_inside_moved_faces(const geo::ProgressiveReplay& replay, std::vector<glm::dvec3>& y,
                              const geo::VertexSplit& s) {
    const glm::dvec3 origin = y[s.parent];
    for (std::uint32_t f : replay.faces_of(s.vertex)) {
        if (f == s.born_faces[0] || f == s.born_faces[1]) continue;
        const glm::uvec3 t = replay.triangles()[f];
        glm::dvec3 middle(0.0);
        for (int k = 0; k < 3; ++k)
            if (t[k] != s.vertex) middle += 0.5 * y[t[k]];
        double share = 1.0 / 3.0;
        for (int i = 0; i < kPlacementHalvings; ++i, share *= 0.5) {
            const glm::dvec3 p = glm::normalize(origin + share * (middle - origin));
            if (in_kernel(replay.faces_of(s.vertex), replay.triangles(), y, s.vertex, p)) {
                y[s.vertex] = p;
                return true;
            }
        }
    }
    return false;
}

// From just off the parent as far towards the new vertex's Tutte target (the normalised mean of its
// neighbours) as its kernel allows: the kernel is convex and holds the start, so the farthest of
// the points 1, 1/2, 1/4, ... of the way that lies in it is a valid place, and a much better start
// than a sliver next to the parent.
bool place(const geo::ProgressiveReplay& replay, std::vector<glm::dvec3>& y, const geo::VertexSplit& s) {
    if (!place_next_to_parent(replay, y, s) && !place_inside_moved_faces(replay, y, s)) return false;
    const glm::dvec3 start = y[s.vertex];
    const VertexStep target =
        optimise_vertex(tutte_energy(replay, y, s.vertex), 1.0, kTutteTolerance, kTutteIterations);
    for (int i = 0; i < kTowardsTargetHalvings; ++i) {
        const glm::dvec3 p = glm::normalize(start + std::ldexp(1.0, -i) * (target.position - start));
        if (in_kernel(replay.faces_of(s.vertex), replay.triangles(), y, s.vertex, p)) {
            y[s.vertex] = p;
            break;
        }
    }
    return true;
}

}  // namespace

SplitRun split_to(geo::ProgressiveReplay& replay, std::vector<glm::dvec3>& y, std::size_t target) {
    SplitRun run;
    while (replay.active_count() < target && !replay.complete()) {
        const geo::VertexSplit& s = replay.split_next();
        ++run.splits;
        y[s.vertex] = y[s.parent];
        if (!place(replay, y, s)) {
            ++run.placement_failures;
            continue;
        }
        // First the new vertex, then its parent (the paper's v1, v2).
        run.kernel_refusals += !relax(replay, y, s.vertex);
        run.kernel_refusals += !relax(replay, y, s.parent);
    }
    return run;
}

}  // namespace gimg::passes::detail

// The priority-queue global optimisation of Kanai's section 4.3, with the mass centre held by a
// Lagrange multiplier (see queue_optimisation.h).
#include "sphere/kanai/queue_optimisation.h"

#include <glm/mat3x3.hpp>

#include <algorithm>
#include <queue>

namespace gimg::passes::detail {

namespace {

struct Entry {
    double key;
    std::uint32_t vertex;
    std::uint32_t stamp;  // valid while it equals the vertex's current stamp
    bool operator<(const Entry& o) const { return key != o.key ? key < o.key : vertex > o.vertex; }
};

// A vertex's local iterations stop when a step changes its energy by less than this share of the
// queue tolerance: each is O(1), so converging them well costs nothing.
constexpr double kLocalShare = 1e-2;
constexpr std::size_t kLocalIterations = 100;
// Times the queue may run dry and be refilled after a new multiplier before we call it done.
constexpr std::size_t kMaxRefills = 100;

// f = lambda / 2 for the constraint sum_v y(v) = 0: the uniform force that cancels the energy
// gradient's component along the Moebius boosts, whose velocity fields are P_v a (P_v the tangent
// projector at y(v)). With grad_v = 2 (W_v y(v) - S_v): f = -(sum P_v)^-1 sum P_v S_v.
glm::dvec3 centring_force(const WeightedGraph& g, const std::vector<glm::dvec3>& y) {
    glm::dmat3 m(0.0);
    glm::dvec3 b(0.0);
    for (std::uint32_t v : g.vertices) {
        const glm::dvec3 p = y[v];
        const glm::dmat3 projector = glm::dmat3(1.0) - glm::outerProduct(p, p);
        m += projector;
        b += projector * g.vertex_energy(v, y).laplacian;  // P_v S_v = P_v L_v since P_v y(v) = 0
    }
    if (!(glm::determinant(m) > 1e-12)) return glm::dvec3(0.0);
    return -(glm::inverse(m) * b);
}

}  // namespace

QueueRun optimise_by_queue(const WeightedGraph& g, std::vector<glm::dvec3>& y, double tolerance, std::size_t max_pops,
                           const std::function<void(std::size_t, double)>& tick) {
    QueueRun run;
    run.energy_before = g.energy(y);
    std::vector<glm::dvec3> candidate(y.size());
    std::vector<std::uint32_t> stamp(y.size(), 0);
    std::priority_queue<Entry> queue;
    glm::dvec3 force(0.0);

    // Tentative vertex conformal (or Tutte, by the weights) optimisation of v; queued when it gains
    // at least `tolerance` and stays in the kernel.
    auto evaluate = [&](std::uint32_t v) {
        ++stamp[v];
        VertexEnergy e = g.vertex_energy(v, y);
        e.laplacian += force;
        const VertexStep step = optimise_vertex(e, 1.0, kLocalShare * tolerance, kLocalIterations);
        const double key = step.energy_before - step.energy_after;
        if (!(key >= tolerance)) return;
        if (!in_kernel(g.adjacency.faces_of_vertex(v), g.triangles, y, v, step.position)) {
            ++run.kernel_refusals;  // stays where it is (the paper restores it) until a neighbour moves
            return;
        }
        candidate[v] = step.position;
        queue.push({key, v, stamp[v]});
    };
    // New multiplier (and, if the map drifted anyway, a Moebius recentring): every key is stale.
    auto refresh = [&] {
        if (glm::length(mass_centre(y, g.vertices)) > kCentreSlack &&
            normalise_mass_centre(y, g.vertices, g.triangles) > 0.0)
            ++run.recentrings;
        force = centring_force(g, y);
        queue = {};
        for (std::uint32_t v : g.vertices) evaluate(v);
    };

    refresh();
    const std::size_t period = std::max<std::size_t>(g.vertices.size(), 256);
    std::size_t refills = 0;
    while (true) {
        if (queue.empty()) {
            if (++refills > kMaxRefills) {
                run.hit_limit = true;
                break;
            }
            refresh();
            if (queue.empty()) break;
        }
        const Entry top = queue.top();
        queue.pop();
        if (top.stamp != stamp[top.vertex]) continue;  // superseded by a later evaluation
        if (run.pops >= max_pops) {
            run.hit_limit = true;
            break;
        }
        y[top.vertex] = candidate[top.vertex];
        ++stamp[top.vertex];
        ++run.pops;
        for (std::uint32_t u : g.adjacency.neighbors(top.vertex)) evaluate(u);
        if (tick && run.pops % 65536 == 0) tick(run.pops, g.energy(y));
        if (run.pops % period == 0) refresh();
    }
    run.energy_after = g.energy(y);
    return run;
}

}  // namespace gimg::passes::detail

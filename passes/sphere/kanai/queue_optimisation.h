#pragma once
// Kanai's global optimisation with a priority queue (section 4.3), for one level of the hierarchy.

#include "sphere/weighted_graph.h"

#include <functional>

namespace gimg::passes::detail {

struct QueueRun {
    std::size_t pops = 0;                            // vertex optimisations applied (the stage's "iterations")
    std::size_t kernel_refusals = 0;                 // tentative steps refused because they left the kernel
    double energy_before = 0.0, energy_after = 0.0;  // the graph's energy (E or F by its weights)
    bool hit_limit = false;       // stopped by a guard (max_pops, or new work after every refit), not by the tolerance
    std::size_t recentrings = 0;  // mass-centre normalisations made on the way
};

// Every active vertex gets a tentative vertex conformal optimisation (optimise_vertex with c = 1,
// run to convergence); key = |F(v) - F0(v)|, the energy it would remove. The largest key is popped
// and its step applied, then the keys of its neighbours are computed again; this stops when the
// largest key is below `tolerance`. A tentative step that would leave the kernel of the vertex's
// one-ring is not queued (the vertex keeps its position, as the paper restores it) until a
// neighbour moves. max_pops is only a guard. `tick` (optional) is called every 65536 pops with the
// pops so far and the energy.
//
// Our addition to the paper: the mass centre (the mean of the points) is held at the origin, the
// constraint Gu's method imposes by normalising after every step. On the sphere the discrete
// energy still falls a little when the whole map slides along a Moebius boost towards one point
// (its big triangles lose area); vertex steps follow that slope without end, and re-centring after
// the fact only starts the slide again (measured: millions of pops and maps collapsing below 8 pi
// on the hand). So the vertex energies carry the constraint's Lagrange multiplier, a uniform pull
// f fitted every V pops (V the level's vertices) and whenever the queue runs dry, which cancels the
// gradient's component along the boosts; should the centre still drift beyond kCentreSlack, a
// Moebius normalisation (normalise_mass_centre) puts it back. Each refit re-keys every vertex.
inline constexpr double kCentreSlack = 1e-3;
QueueRun optimise_by_queue(const WeightedGraph& g, std::vector<glm::dvec3>& y, double tolerance, std::size_t max_pops,
                           const std::function<void(std::size_t, double)>& tick = {});

}  // namespace gimg::passes::detail

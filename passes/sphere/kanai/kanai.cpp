// Kanai (2005), "Robust and fast calculation of conformal spherical parameterization", chapter 4:
// a progressive mesh; a sphere map of its coarse base mesh; vertex splits replayed with the vertex
// Tutte optimisation and the kernel check; at every `growth`-fold increase of the vertex count and
// at the full mesh, the priority-queue global conformal optimisation.
//
// Where we chose:
//  - the paper maps the base mesh with Alexa's method; ours refines a tetrahedron with the same
//    kernel-checked splits (base_map.h), one-to-one by construction;
//  - a split's new vertex is placed next to its parent inside the wedge its two new faces need,
//    then moved towards its neighbours' mean as far as its kernel allows (split_refinement.h);
//  - the step constants are the paper's c_t = c_c = 1 on Laplacians normalised by the weights
//    (sphere_steps.h); the per-vertex iterations run to convergence;
//  - the queue optimisation holds the mass centre at the origin (queue_optimisation.h), which the
//    paper does not do but needs: without it the maps slide towards a point;
//  - the kernel check keeps every triangle counter-clockwise by a rounding margin, so no step,
//    including the Moebius re-centring, can leave a flipped triangle behind.
#include "gimg/passes/sphere.h"

#include "sphere/hierarchy/base_map.h"
#include "sphere/weighted_graph.h"
#include "gimg/geometry/progressive_replay.h"
#include "sphere/kanai/queue_optimisation.h"
#include "sphere/hierarchy/split_refinement.h"

#include "gimg/geometry/error.h"

#include <chrono>
#include <cmath>
#include <string>

namespace gimg::passes {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Guard on one level's queue: far above what the tolerance needs on any mesh we have seen.
constexpr std::size_t kMaxPopsPerVertex = 100000;

struct Run {
    const geo::Mesh& mesh;
    const KanaiOptions& options;
    Clock::time_point t0;
    SphereResult& result;
    std::vector<std::string> warnings;

    // Splits up to `count` vertices, then one global optimisation; returns the stage.
    SphereStage level(geo::ProgressiveReplay& replay, std::size_t count, const std::string& name) {
        const auto start = Clock::now();
        const detail::SplitRun splits = detail::split_to(replay, result.positions, count);
        if (splits.placement_failures)
            warnings.push_back(name + ": " + std::to_string(splits.placement_failures) +
                               " split vertices could not be placed");
        const detail::WeightedGraph g =
            detail::make_weighted_graph(mesh, replay.live_triangles(), detail::EdgeWeights::Cotangent);
        auto tick = [&](std::size_t pops, double energy) {
            if (options.progress) options.progress(name, pops, energy, 0, seconds_since(t0));
        };
        const detail::QueueRun q = detail::optimise_by_queue(g, result.positions, options.queue_tolerance,
                                                             kMaxPopsPerVertex * g.vertices.size(), tick);
        if (q.hit_limit)
            warnings.push_back(name + ": the queue optimisation stopped at a guard after " + std::to_string(q.pops) +
                               " pops");
        SphereStage stage;
        stage.name = name;
        stage.vertices = g.vertices.size();
        stage.iterations = q.pops;
        stage.energy = g.energy(result.positions);
        stage.seconds = seconds_since(start);
        const std::size_t flips = detail::count_flips(g.triangles, result.positions);
        if (flips) warnings.push_back(name + ": " + std::to_string(flips) + " flipped triangles");
        if (options.progress) options.progress(name, q.pops, stage.energy, flips, seconds_since(t0));
        return stage;
    }
};

}  // namespace

SphereResult sphere_kanai(const geo::Mesh& mesh, const KanaiOptions& options) {
    check_sphere_input(mesh);
    if (!(options.queue_tolerance > 0.0) || !std::isfinite(options.queue_tolerance))
        throw geo::InputError("kanai: the queue tolerance must be a positive number");
    const auto t0 = Clock::now();
    SphereResult result;
    result.positions.assign(mesh.vertex_count(), glm::dvec3(0.0));
    Run run{mesh, options, t0, result, {}};

    // The progressive mesh and the base map (see base_map.h).
    detail::HierarchyStart start(mesh, options.base_vertices, options.growth, result.positions, result.stages,
                                 run.warnings, t0);
    const std::vector<std::size_t>& counts = start.counts;
    geo::ProgressiveReplay& replay = start.replay;
    const detail::BaseMapRun& base = start.base;
    if (options.progress) options.progress("base map", base.vertex_steps, base.energy, base.flips, seconds_since(t0));

    // Kanai's hierarchy: split to growth x the vertices, optimise globally; at the full mesh once more
    // (the last level). A base that already is the full mesh is optimised once.
    for (std::size_t i = counts.size() == 1 ? 0 : 1; i < counts.size(); ++i)
        result.stages.push_back(run.level(
            replay, counts[i], "level " + std::to_string(i) + " (" + std::to_string(counts[i]) + " vertices)"));

    for (const std::string& w : run.warnings) result.note += (result.note.empty() ? "" : "; ") + w;
    result.converged = run.warnings.empty();
    return result;
}

}  // namespace gimg::passes

// gimg's spherical conformal map, by one of two routes.
//
// The direct route (tried first, HarmonicSphereOptions::direct): Choi, Lam and Lui's pinned-triangle
// harmonic map (pinned_start.h) as the start, then the planar polish around the start's accurate
// pole: two multigrid-preconditioned conjugate gradient solves, a local repair of folds and a
// short relaxation, all on the render graph, with no hierarchy to build. Kept when it flips
// nothing and covers the sphere once.
//
// The hierarchy (where the pinned-triangle start is rejected): Kanai's hierarchy (the same progressive
// mesh, base map and kernel-checked vertex splits as sphere_kanai) with the global conformal
// optimisation of every level done by GpuRelaxation: colour-by-colour parallel sweeps on the
// render graph, each vertex moving to the minimiser of its local energy on the sphere as far as no
// triangle flips, with the energy, flip count and mass centre reduced on the GPU and read back
// every K iterations, then the same polish around the relaxed map's largest triangle. The step
// needs no constant: the local minimiser is exact, and halving only guards the kernel.
//
// Points are float64 throughout: conformal maps shrink protrusions to triangles far below
// float32's resolution on the unit sphere (1e-15 on triceratops), where a float32 orientation
// test would call flips at random.
#include "gimg/passes/sphere.h"

#include "sphere/hierarchy/base_map.h"
#include "sphere/harmonic/pinned_start.h"
#include "sphere/harmonic/relaxation_mesh_check.h"
#include "solvers/conjugate_gradients.h"
#include "gimg/geometry/progressive_replay.h"
#include "sphere/harmonic/relaxation_mesh.h"
#include "sphere/harmonic/relaxation.h"
#include "sphere/harmonic/fold_repair.h"
#include "sphere/hierarchy/split_refinement.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/vertex_order.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <numbers>
#include <string>

namespace gimg::passes {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Tutte phase of a level whose splits left degenerate triangles: at most this many checks of
// this many sweeps.
constexpr std::size_t kMaxTutteChecks = 8;
constexpr std::uint32_t kTutteSweepsPerCheck = 8;

// Sweeps between two Moebius recentrings on a level of n vertices. The discrete energy falls when
// the whole map slides along a Moebius boost towards one point, the faster the coarser the mesh:
// with 4 sweeps between recentrings the icosahedron slides into a point, with 1 it stays itself
// (measured, tests/passes/test_sphere_harmonic.cpp). Levels of a few thousand vertices and more get
// the caller's K.
std::uint32_t sweeps_per_check(std::size_t n, std::uint32_t k) {
    return std::uint32_t(std::clamp<std::size_t>(n / 128, 1, k));
}

bool indices_in_range(const geo::Mesh& mesh) {
    return std::all_of(mesh.triangles.begin(), mesh.triangles.end(),
                       [n = mesh.vertex_count()](const glm::uvec3& t) { return t.x < n && t.y < n && t.z < n; });
}

bool all_points_finite(const geo::Mesh& mesh) {
    return std::all_of(mesh.positions.begin(), mesh.positions.end(), [](const glm::dvec3& p) {
        return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    });
}

void check_options(const HarmonicSphereOptions& o) {
    if (o.base_vertices < 4) throw geo::InputError("gpu sphere: base_vertices must be at least 4");
    if (!(o.growth > 1.0) || !std::isfinite(o.growth)) throw geo::InputError("gpu sphere: growth must be above 1");
    if (o.iterations_per_check == 0) throw geo::InputError("gpu sphere: iterations_per_check must be at least 1");
    if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance))
        throw geo::InputError("gpu sphere: tolerance must be positive");
    if (o.max_iterations_per_level == 0)
        throw geo::InputError("gpu sphere: max_iterations_per_level must be at least 1");
}

// The level mesh of the replay's live faces in local ids (the activation order: a mesh of n
// vertices holds exactly those with activation index < n), at the original positions.
geo::Mesh level_mesh(const geo::Mesh& mesh, const geo::ProgressiveReplay& replay,
                     const std::vector<std::uint32_t>& activation, const std::vector<std::uint32_t>& vertex_of) {
    geo::Mesh level;
    const std::size_t n = replay.active_count();
    level.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i) level.positions[i] = mesh.positions[vertex_of[i]];
    level.triangles = replay.live_triangles();
    for (glm::uvec3& t : level.triangles) t = {activation[t.x], activation[t.y], activation[t.z]};
    return level;
}

struct SettleRun {
    std::size_t iterations = 0;  // the level's sweeps so far, these included
    double energy = 0.0;
    std::size_t flips = 0;
    bool converged = false;
};

// Checks of K sweeps until the energy changed by less than options.tolerance per sweep, relative
// to it, or the level's budget of sweeps is spent.
SettleRun settle(detail::GpuRelaxation& relax, std::size_t vertex_count, const HarmonicSphereOptions& options,
                 std::size_t iterations, double energy, const std::string& name, Clock::time_point t0, double& gpu_ms) {
    SettleRun run{iterations, energy, 0, false};
    while (run.iterations < options.max_iterations_per_level) {
        const auto k = std::uint32_t(std::min<std::size_t>(sweeps_per_check(vertex_count, options.iterations_per_check),
                                                           options.max_iterations_per_level - run.iterations));
        const detail::RelaxCheck check = relax.run(k, false);
        run.iterations += k;
        gpu_ms += relax.last_gpu_ms();
        const detail::MapStats& now = check.recentre_kept ? check.recentred : check.relaxed;
        // How much the energy changed per iteration, relative to it, between the kept states of
        // two checks (the sweeps lower it; the conformal recentring barely changes it).
        const double change = std::abs(run.energy - now.energy) / (now.energy * double(k));
        run.energy = now.energy;
        run.flips = now.flips;
        if (options.progress) options.progress(name, run.iterations, run.energy, run.flips, seconds_since(t0));
        if (!std::isfinite(run.energy)) break;
        if (change < options.tolerance) {
            run.converged = true;
            break;
        }
    }
    return run;
}

// Levels the polish follows (HarmonicSphereOptions::loose_levels_above) settle to
// kLooseToleranceScale x the tolerance in checks of kLooseSweepsPerCheck sweeps: bunny, armadillo
// and armadillo_loop1 end with the same angles to 0.001 degree mean and the same conformal ratio
// to 3e-5, in 16 sweeps a level instead of 64-184.
constexpr double kLooseToleranceScale = 100.0;
constexpr std::uint32_t kLooseSweepsPerCheck = 8;

HarmonicSphereOptions loose_level_options(HarmonicSphereOptions o) {
    o.tolerance *= kLooseToleranceScale;
    o.iterations_per_check = std::min(o.iterations_per_check, kLooseSweepsPerCheck);
    return o;
}

// The planar polish (chart_problem.h): conjugate gradients until the error's energy norm is this
// small relative to the solution's (1e-7 gives bunny, armadillo and armadillo_loop1 the same
// angles as 1e-9, but leaves dino with 301 folds the untangling cannot repair, so its map comes
// from the hierarchy, 5x slower and 47 degrees mean instead of 34; 1e-6 raises armadillo's
// largest from 57 to 77 degrees). 1e-8 was at that edge: with the preconditioner of the time,
// stopping at 9.9e-9 after 15 iterations, dino's polish folded 328 triangles whose repair left a
// map the centring could not move (256 sweeps of relaxation, 44 degrees mean); with 5e-9 it
// stopped at 2.1e-9 after 17 (17 degrees mean, 0.08 s). Dino's result still moves with the last
// digits of its solve (26.5 degrees mean after 11 iterations since the multigrid keeps strong
// connections only). Checked first after kCgIterationsPerCheck iterations (the polish needs 8-31
// on the shared meshes), at most kMaxCgIterations.
constexpr double kCgTolerance = 5e-9;
constexpr std::uint32_t kCgIterationsPerCheck = 8;
constexpr std::size_t kMaxCgIterations = 2000;
// The relaxation after the polish starts next to its minimum: checks of at most this many sweeps.
// With 4 instead of 8 armadillo_loop1 stops after 4 sweeps instead of 8, bunny after 8 instead of
// 16, with the same convergence test and mean angles within 0.002 degrees.
constexpr std::uint32_t kPolishSweepsPerCheck = 4;

// The progress line of a conjugate gradient solve.
std::function<void(std::size_t, double)> cg_progress(const std::string& what, double energy,
                                                     const HarmonicSphereOptions& options, Clock::time_point t0) {
    if (!options.progress) return {};
    return [what, energy, &options, t0](std::size_t iterations, double residual) {
        char stage[96];
        std::snprintf(stage, sizeof stage, "%s (residual %.1e)", what.c_str(), residual);
        options.progress(stage, iterations, energy, 0, seconds_since(t0));
    };
}

struct PolishRun {
    bool kept = false;
    std::string why;  // when rejected
};

// Solves the planar problem of the map `y` with the cap around `pole`, projects back, settles the
// relaxation from there and keeps the result (in `y`) when it has no flipped triangle and an
// energy at most 0.1% above `energy`, the energy of `y`: on the hierarchy's route `y` is the
// relaxed map, and the harmonic map in the plane and the relaxed map minimise the same energy up to
// discretisation, so more means the solve went wrong.
PolishRun polish_in_plane(Context& ctx, const detail::RelaxationMesh& level, std::vector<glm::dvec3>& y,
                          const glm::dvec3& pole, double energy, const HarmonicSphereOptions& options,
                          Clock::time_point t0, SphereResult& result) {
    const auto start = Clock::now();
    const detail::ChartProblem problem = detail::make_chart_problem(level, y, pole);
    if (std::any_of(problem.diagonal.begin(), problem.diagonal.end(), [](double d) { return !(d > 0.0); }))
        return {false, "a vertex's cotangent weights sum to zero or less"};
    detail::Multigrid mg;
    try {
        mg = detail::build_multigrid(problem);
    } catch (const geo::InputError& e) {
        return {false, e.what()};
    }
    result.stages.push_back({"chart solve: problem and multigrid setup (" + std::to_string(mg.levels.size() + 1) +
                                 " levels, " + std::to_string(mg.coarsest_rows()) + " rows solved densely)",
                             problem.rows(), 0, seconds_since(start), energy});
    const auto solve_start = Clock::now();
    const detail::CgSolve solve =
        detail::solve_cg_gpu(ctx, problem, mg, kCgTolerance, kCgIterationsPerCheck, kMaxCgIterations,
                             options.timestamps, cg_progress("chart solve", energy, options, t0));
    result.gpu_ms += solve.gpu_ms;
    const std::string solve_name =
        "chart solve: conjugate gradients (" + std::to_string(problem.rows()) + " free vertices)";
    std::vector<glm::dvec3> polished = detail::sphere_points_from_chart(problem, y, solve.x);
    const detail::MapStats polished_stats = detail::map_stats_cpu(level, polished);
    result.stages.push_back(
        {solve_name, problem.rows(), solve.iterations, seconds_since(solve_start), polished_stats.energy});
    if (!std::isfinite(solve.residual))
        return {false, "conjugate gradients broke down (the problem or its preconditioner is not positive definite)"};
    if (!solve.converged(kCgTolerance))
        return {false, "conjugate gradients stopped at residual " + std::to_string(solve.residual)};
    detail::MapStats stats = polished_stats;  // of `polished` as it is now
    if (stats.flips > 0) {
        // Negative cotangent weights (obtuse triangles) folded a few triangles: repair them locally.
        const auto untangle_start = Clock::now();
        const detail::FoldRepair untangled = detail::repair_folds(level, polished);
        stats = detail::map_stats_cpu(level, polished);
        result.stages.push_back({"chart solve: fold repair (" + std::to_string(untangled.flips_before) +
                                     " flipped triangles, " + std::to_string(untangled.flips_after) + " left, " +
                                     std::to_string(untangled.moves) + " moves)",
                                 level.vertex_count(), untangled.moves, seconds_since(untangle_start), stats.energy});
        if (untangled.flips_after > 0)
            return {false,
                    std::to_string(untangled.flips_after) + " flipped triangles the untangling could not repair"};
    }

    // The solve pinned a cap and the projection crowds the map towards it (armadillo_loop1: mass
    // centre 0.91 from the origin). Centred first, the relaxation settles in 1-2 checks of 8
    // sweeps instead of 5-6 (bunny, armadillo_loop1), with the same angles or better.
    const auto centre_start = Clock::now();
    const detail::CentreRun centred = detail::centre_mass_cpu(level, polished, stats);
    stats = centred.stats;
    result.stages.push_back(
        {std::string("chart solve: Moebius centring") + (centred.kept ? "" : " (skipped: it would flip triangles)"),
         level.vertex_count(), centred.steps, seconds_since(centre_start), stats.energy});

    const auto relax_start = Clock::now();
    detail::GpuRelaxation relax(ctx, level, polished);
    relax.set_timestamps(options.timestamps);
    const std::string name = "chart solve: relaxation";
    HarmonicSphereOptions relax_options = options;
    relax_options.iterations_per_check = std::min(options.iterations_per_check, kPolishSweepsPerCheck);
    const SettleRun settled =
        settle(relax, level.vertex_count(), relax_options, 0, stats.energy, name, t0, result.gpu_ms);
    result.stages.push_back(
        {name, level.vertex_count(), settled.iterations, seconds_since(relax_start), settled.energy});
    if (settled.flips) return {false, std::to_string(settled.flips) + " flipped triangles"};
    if (!(settled.energy <= energy * 1.001))
        return {false, "energy " + std::to_string(settled.energy) + " against " + std::to_string(energy)};
    y = relax.positions();
    return {true, ""};
}

// The direct route's start solves to this relative residual: it only has to place the polish's
// cap (1% of the vertices, around the start's accurate pole) and give the polish its first guess.
// bunny and armadillo end with the same angles and conformal ratio from 1e-4 to 1e-6;
// armadillo_loop1 with 1.158 degrees mean from 3e-5 and 1e-5 (14 iterations), 1.155 from 1e-6
// (20), but 1.242 from 1e-4 (12): its cap is placed badly. 1e-3 raises bunny's mean from 0.83 to
// 0.86 degrees.
constexpr double kStartTolerance = 1e-5;

// The direct route (pinned_start.h): Choi, Lam and Lui's pinned-triangle map as the start, the
// polish around its accurate pole. Kept when the polish is (no flips, energy at most 0.1% above
// the start's) and the map covers the sphere exactly once; the map is then in result.positions.
// `before_gpu` runs once the start's CPU setup is done (sphere_harmonic waits there for its input check).
PolishRun direct_route(Context& ctx, const geo::Mesh& mesh, const detail::RelaxationMesh& level,
                       const HarmonicSphereOptions& options, const std::function<void()>& before_gpu,
                       Clock::time_point t0, SphereResult& result) {
    const auto start_clock = Clock::now();
    detail::PinnedStart start = detail::pinned_start_gpu(ctx, mesh, level, kStartTolerance, options.timestamps,
                                                         cg_progress("harmonic start", 0.0, options, t0), before_gpu);
    result.gpu_ms += start.gpu_ms;
    const double start_energy = start.why.empty() ? detail::map_stats_cpu(level, start.y).energy : std::nan("");
    result.stages.push_back({"harmonic start: pinned-triangle map by conjugate gradients (" +
                                 std::to_string(start.free_vertices) + " free vertices)",
                             start.free_vertices, start.iterations, seconds_since(start_clock), start_energy});
    if (!start.why.empty()) return {false, "harmonic start: " + start.why};
    std::vector<glm::dvec3> y = std::move(start.y);
    PolishRun polish = polish_in_plane(ctx, level, y, start.accurate_pole, start_energy, options, t0, result);
    if (!polish.kept) return polish;
    const double covers = detail::total_solid_angle(level, y) / (4.0 * std::numbers::pi);
    if (!(std::abs(covers - 1.0) < 1e-6))
        return {false, "the map covers the sphere " + std::to_string(covers) + " times"};
    result.positions = std::move(y);
    return {true, ""};
}

// Both routes; `mesh_level` is the mesh's level (for the direct route; empty when the direct route
// is off). `wait_for_check` returns once the mesh is known to be good (it throws when it is not):
// called before any GPU work, and before the hierarchy, whose CPU setup assumes good input.
SphereResult map_to_sphere(Context& ctx, const geo::Mesh& mesh, const detail::RelaxationMesh& mesh_level,
                           const HarmonicSphereOptions& options, const std::function<void()>& wait_for_check) {
    const auto t0 = Clock::now();
    SphereResult result;
    std::vector<std::string> warnings;  // what leaves the map in doubt: converged = false
    std::vector<std::string> remarks;   // what happened on the way and was put right
    if (options.plane_polish && options.direct) {
        const PolishRun direct = direct_route(ctx, mesh, mesh_level, options, wait_for_check, t0, result);
        if (direct.kept) return result;
        remarks.push_back("pinned-triangle start rejected (" + direct.why + "), the hierarchy made the map");
    }
    wait_for_check();
    result.positions.assign(mesh.vertex_count(), glm::dvec3(0.0));

    // Not t0: a rejected pinned-triangle start came first.
    detail::HierarchyStart hierarchy(mesh, options.base_vertices, options.growth, result.positions, result.stages,
                                     warnings, Clock::now());
    const geo::ProgressiveMesh& pm = hierarchy.pm;
    const std::vector<std::size_t>& counts = hierarchy.counts;
    geo::ProgressiveReplay& replay = hierarchy.replay;
    const std::vector<std::uint32_t> activation = geo::activation_order(pm);
    std::vector<std::uint32_t> vertex_of(activation.size());
    for (std::uint32_t v = 0; v < activation.size(); ++v) vertex_of[activation[v]] = v;

    for (std::size_t i = counts.size() == 1 ? 0 : 1; i < counts.size(); ++i) {
        const auto level_start = Clock::now();
        const std::string name = "level " + std::to_string(i) + " (" + std::to_string(counts[i]) + " vertices)";
        const detail::SplitRun splits = detail::split_to(replay, result.positions, counts[i]);
        const detail::RelaxationMesh level =
            detail::build_relaxation_mesh(level_mesh(mesh, replay, activation, vertex_of));
        std::vector<glm::dvec3> y(level.vertex_count());
        for (std::size_t v = 0; v < y.size(); ++v) y[v] = result.positions[vertex_of[v]];

        detail::GpuRelaxation relax(ctx, level, y);
        relax.set_timestamps(options.timestamps);
        const detail::MapStats start = detail::map_stats_cpu(level, y);
        double energy = start.energy;
        std::size_t iterations = 0;
        // A split that found no room left its vertex on its parent (degenerate triangles): Tutte
        // sweeps (uniform weights) first, as Kanai's Tutte phase, spread such vertices into their
        // neighbours' middle; the grade rule lets a move mend a triangle, never spoil one.
        std::size_t kernel_failures = start.kernel_failures;
        for (std::size_t tutte = 0; kernel_failures > 0 && tutte < kMaxTutteChecks; ++tutte) {
            const detail::RelaxCheck check = relax.run(kTutteSweepsPerCheck, true);
            iterations += kTutteSweepsPerCheck;
            result.gpu_ms += relax.last_gpu_ms();
            const detail::MapStats& now = check.recentre_kept ? check.recentred : check.relaxed;
            energy = now.energy;
            kernel_failures = now.kernel_failures;
        }
        if (splits.placement_failures) {
            // Mended by the Tutte phase it is worth knowing, not a failure.
            const std::string what =
                name + ": " + std::to_string(splits.placement_failures) + " split vertices could not be placed";
            if (kernel_failures == 0)
                remarks.push_back(what + " (the Tutte phase placed them)");
            else
                warnings.push_back(what + ", " + std::to_string(kernel_failures) +
                                   " triangles fail the kernel test after the Tutte phase");
        }
        // Under the polish big levels only have to hand a flip-free map to the next: settled
        // loosely (loose_level_options); the finest settles in full after all when the polish is
        // rejected.
        const bool last = i + 1 == counts.size();
        const bool loose = options.plane_polish && level.vertex_count() > options.loose_levels_above;
        const HarmonicSphereOptions level_options = loose ? loose_level_options(options) : options;
        SettleRun settled =
            settle(relax, level.vertex_count(), level_options, iterations, energy, name, t0, result.gpu_ms);
        y = relax.positions();
        result.stages.push_back(
            {name, level.vertex_count(), settled.iterations, seconds_since(level_start), settled.energy});
        bool polished = false;
        if (options.plane_polish && last && settled.flips == 0 && std::isfinite(settled.energy)) {
            const PolishRun polish = polish_in_plane(ctx, level, y, detail::largest_triangle_pole(level, y),
                                                     settled.energy, options, t0, result);
            polished = polish.kept;
            if (!polished) remarks.push_back("chart solve rejected: " + polish.why);
        }
        if (loose && last && !polished) {
            const auto full_start = Clock::now();
            const std::string full_name = name + ", relaxed in full without the chart solve";
            settled = settle(relax, level.vertex_count(), options, 0, settled.energy, full_name, t0, result.gpu_ms);
            y = relax.positions();
            result.stages.push_back(
                {full_name, level.vertex_count(), settled.iterations, seconds_since(full_start), settled.energy});
        }
        if (!std::isfinite(settled.energy)) warnings.push_back(name + ": the energy is not finite");
        if (!settled.converged && std::isfinite(settled.energy))
            warnings.push_back(name + ": stopped at " + std::to_string(settled.iterations) + " iterations");
        if (settled.flips) warnings.push_back(name + ": " + std::to_string(settled.flips) + " flipped triangles");
        for (std::size_t v = 0; v < y.size(); ++v) result.positions[vertex_of[v]] = y[v];
    }
    for (const std::string& w : warnings) result.note += (result.note.empty() ? "" : "; ") + w;
    for (const std::string& r : remarks) result.note += (result.note.empty() ? "" : "; ") + r;
    result.converged = warnings.empty();
    return result;
}

}  // namespace

SphereResult sphere_harmonic(Context& ctx, const geo::Mesh& mesh, const HarmonicSphereOptions& options) {
    // The input must be closed, manifold, genus 0 (check_sphere_input). A mesh without indices in
    // range and finite points is checked first, alone. The direct route lays out the mesh's level
    // anyway, and a level that exists leaves little to check (relaxation_mesh_check.h): that is checked
    // here, and only a mesh that fails it goes to check_sphere_input, for the message. Otherwise
    // the check (topology, components, genus: 50-60 ms on armadillo_loop1) runs on a second thread
    // while this one renumbers the vertices, and the map waits for it before any GPU work. Either
    // way the check's message comes first whenever it has one.
    if (!indices_in_range(mesh) || !all_points_finite(mesh)) check_sphere_input(mesh);
    const bool direct = options.plane_polish && options.direct;
    std::future<void> checked;
    if (!direct) checked = std::async(std::launch::async, [&mesh] { check_sphere_input(mesh); });
    // The input's message first, when it has one, wherever something else went wrong.
    auto input_message_first = [&] {
        if (checked.valid())
            checked.get();
        else
            check_sphere_input(mesh);
    };
    std::vector<std::uint32_t> order;
    geo::Mesh renumbered;
    detail::RelaxationMesh level;
    bool input_checked = false;  // check_sphere_input has run here
    try {
        check_options(options);
        if (!ctx.device_info().shader_float64)
            throw Error(
                ErrorKind::Unsupported,
                "gpu sphere: the device has no float64 in shaders (shaderFloat64); use --method kanai or linear");
        if (options.plane_polish && !ctx.device_info().storage_image_extended_formats)
            throw Error(ErrorKind::Unsupported,
                        "gpu sphere: the device has no two-channel storage images for the polish's "
                        "multigrid (shaderStorageImageExtendedFormats); use --method kanai or linear");
        // Solved with the vertices renumbered along a space-filling curve, so that the passes'
        // gathers of neighbours hit the cache (geometry/vertex_order.h): armadillo_loop1's
        // conjugate gradient iterations and relaxation sweeps took 30 % less time.
        order = geo::spatial_vertex_order(mesh);
        renumbered = geo::reorder_vertices(mesh, order);
        if (direct) {
            level = detail::build_relaxation_mesh(renumbered);
            if (!detail::relaxation_mesh_is_sphere(renumbered, level)) {
                input_checked = true;
                check_sphere_input(mesh);
            }
        }
    } catch (...) {
        if (!input_checked) input_message_first();
        throw;
    }
    bool check_done = false;
    const std::function<void()> wait_for_check = [&] {
        if (check_done) return;
        check_done = true;
        if (checked.valid()) checked.get();
    };
    SphereResult result;
    try {
        result = map_to_sphere(ctx, renumbered, level, options, wait_for_check);
    } catch (...) {
        wait_for_check();  // the input's message first, when it has one
        throw;
    }
    wait_for_check();
    result.positions = geo::original_vertex_order(result.positions, order);
    return result;
}

}  // namespace gimg::passes

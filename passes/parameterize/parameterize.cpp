// The square map and its iterations: build the weighted Tutte system with the boundary fixed, solve
// it (GPU or the CPU twin), reweigh, solve again from the last map, until E_sigma stops falling.
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/solvers.h"
#include "parameterize/reweighting.h"
#include "parameterize/tutte_system.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

namespace gimg::passes {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string scientific(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2e", x);
    return text;
}

constexpr const char* kVariantNames[] = {"tutte", "floater", "stretch", "density", "uniform3d", "curvature"};
// The iterates project_start combines for the next reweighted solve.
constexpr std::size_t kPastIterates = 4;
// candidates_size's samples each way: enough to tell a crushed map (table_piece: 10 times the
// start's RMS) from the start, at a fifth of select's cost.
constexpr std::size_t kCandidateSamples = 10'000;

}  // namespace

const char* variant_name(ParameterizeVariant variant) { return kVariantNames[int(variant)]; }

std::optional<ParameterizeVariant> parse_variant(const std::string& name) {
    for (int i = 0; i < 6; ++i)
        if (name == kVariantNames[i]) return ParameterizeVariant(i);
    return std::nullopt;
}

std::size_t count_flipped(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv) {
    std::size_t n = 0;
    for (double a : detail::uv_face_areas(mesh, uv)) n += a < 0.0;
    return n;
}

Parameterization parameterize_square(Context* ctx, const geo::Mesh& mesh, const ParameterizeOptions& options,
                                     const std::function<void(const IterationReport&)>& on_iteration) {
    const auto t0 = Clock::now();
    const std::uint64_t submitted_before = ctx ? ctx->submission_count() : 0;
    const double waited_before = ctx ? ctx->device_wait_seconds() : 0.0;
    check_disk_mesh(mesh);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    Parameterization out;
    out.boundary = options.boundary ? *options.boundary : square_boundary(mesh, adj, options.corners);
    if (out.boundary.uv.size() != out.boundary.loop.size())
        throw geo::InputError("the given boundary has " + std::to_string(out.boundary.uv.size()) + " places for " +
                              std::to_string(out.boundary.loop.size()) + " vertices");
    for (std::uint32_t v : out.boundary.loop)
        if (v >= mesh.vertex_count()) throw geo::InputError("the given boundary names a vertex the mesh lacks");
    const std::size_t n = mesh.vertex_count();

    detail::ReweightingInput in;
    in.variant = options.variant;
    in.adjacency = &adj;
    in.boundary_factors_on_ratio = options.boundary_factors_on_ratio;
    in.interior.assign(n, 1);
    in.corner.assign(n, 0);
    std::vector<glm::dvec2> fixed_uv(n, glm::dvec2(0.0));
    for (std::size_t k = 0; k < out.boundary.loop.size(); ++k) {
        in.interior[out.boundary.loop[k]] = 0;
        fixed_uv[out.boundary.loop[k]] = out.boundary.uv[k];
    }
    for (std::uint32_t c : out.boundary.corners) in.corner[c] = 1;
    in.face_area_3d = geo::face_areas(mesh);
    in.ring_area_3d = detail::ring_areas(adj, in.face_area_3d);
    if (options.variant == ParameterizeVariant::Curvature)
        in.feature = curvature_feature(mesh, adj, options.curvature_root);

    std::vector<double> weights;
    if (options.variant == ParameterizeVariant::Tutte) {
        weights.assign(adj.vertex_vertices.size(), 0.0);
        for (std::size_t i = 0; i < n; ++i) {
            const auto nb = adj.neighbors(i);
            if (in.interior[i])
                for (std::size_t k = 0; k < nb.size(); ++k)
                    weights[adj.vertex_vertex_offsets[i] + k] = 1.0 / double(nb.size());
        }
    } else {
        weights = floater_weights(mesh, adj);
    }

    // Every solve is preconditioned by the V-cycle of the first system's hierarchy: the reweighted
    // systems drift from it, but a rebuilt one saves no iterations (mannequin_devil: 8-20 a solve
    // either way) and costs 20 ms each time. A solve takes 8-80 iterations, checked every 4.
    PreconditionerCache hierarchy;
    // The weighted system from `start` to a relative residual of `tolerance`; adds its iterations to
    // `solver_iterations`.
    // Each reweighted solve starts from the combination of the last iterates that leaves the least
    // residual (project_start): mannequin_devil's curvature run takes 137 solver iterations instead of
    // 271, its density run 470 instead of 974 (final solves included). More than 4 iterates save no more.
    std::vector<std::vector<double>> past;  // oldest first
    // A solve stops at the first check under the tolerance. The CPU twin knows its residual after
    // every iteration; a GPU reads it back after a submission, which costs a real GPU about as much
    // as a few iterations, so it checks every 4. On a CPU device (lavapipe) the read-back is a
    // function call: checking every iteration there saved a tenth of the iterations (mannequin_devil,
    // curvature: 119 against 131) and about as much of the map's time.
    const std::uint32_t iterations_per_check = !ctx || ctx->device_info().type == VK_PHYSICAL_DEVICE_TYPE_CPU ? 1u : 4u;
    double solving = 0.0;  // seconds in solve_to so far
    auto close_run = [&] {
        out.seconds = seconds_since(t0);
        out.solve_seconds = solving;
        if (ctx) {
            out.submissions = ctx->submission_count() - submitted_before;
            out.device_wait_seconds = ctx->device_wait_seconds() - waited_before;
        }
    };
    auto solve_to = [&](const std::vector<glm::dvec2>& start, double tolerance, std::size_t& solver_iterations,
                        bool from_past = false) {
        const auto solve_start = Clock::now();
        LinearSystem system = detail::tutte_system(adj, weights, in.interior, fixed_uv, start);
        if (from_past) project_start(system, past);
        const SolveOptions solve_options{.tolerance = tolerance,
                                         .max_iterations = options.max_solver_iterations,
                                         .iterations_per_check = iterations_per_check,
                                         .preconditioner = Preconditioner::Multigrid,
                                         .reuse = &hierarchy};
        const SolveResult r =
            ctx ? solve_general(*ctx, system, solve_options) : solve_general_cpu(system, solve_options);
        if (!r.converged)
            throw geo::InputError("the parameterization's linear system did not converge (relative residual " +
                                  scientific(r.residual) + " after " + std::to_string(r.iterations) + " iterations)");
        solver_iterations += r.iterations;
        std::vector<glm::dvec2> uv(n);
        for (std::size_t i = 0; i < n; ++i) uv[i] = {r.x[2 * i], r.x[2 * i + 1]};
        solving += seconds_since(solve_start);
        return uv;
    };
    const bool reweighting =
        options.variant != ParameterizeVariant::Tutte && options.variant != ParameterizeVariant::Floater;
    const double iterate_tolerance = reweighting && !options.keep_iterates
                                         ? std::max(options.iterate_tolerance, options.solve_tolerance)
                                         : options.solve_tolerance;
    // An iterate: loosely solved, and solved on to full accuracy if that one folds, and on to
    // fold_tolerance if it still does.
    auto solve = [&](const std::vector<glm::dvec2>& start, IterationReport& report) {
        const double before = solving;
        std::vector<glm::dvec2> uv = solve_to(start, iterate_tolerance, report.solver_iterations, !past.empty());
        if (iterate_tolerance > options.solve_tolerance && count_flipped(mesh, uv) > 0)
            uv = solve_to(uv, options.solve_tolerance, report.solver_iterations);
        if (options.fold_tolerance < options.solve_tolerance && count_flipped(mesh, uv) > 0)
            uv = solve_to(uv, options.fold_tolerance, report.solver_iterations);
        report.solve_seconds = solving - before;
        return uv;
    };
    // Measures of an iterate; returns its L2 stretch's per-face squares for the stretch variant and
    // keeps its 2D one-ring areas for the next reweighting.
    std::vector<double> ring_area_2d;
    auto measure = [&](const std::vector<glm::dvec2>& uv, IterationReport& report) {
        const std::vector<double> uv_faces = detail::uv_face_areas(mesh, uv);
        ring_area_2d = detail::ring_areas(adj, uv_faces);
        report.area_spread = detail::area_spread(detail::equalised_areas(in, ring_area_2d), in.interior);
        std::vector<double> stretch = detail::face_stretch_squared(mesh, uv, in.face_area_3d);
        report.l2_stretch = detail::l2_stretch(stretch, in.face_area_3d);
        report.flipped = 0;
        for (double a : uv_faces) report.flipped += a < 0.0;
        return stretch;
    };
    std::optional<geo::TriangleBvh> mesh_bvh;  // for measuring the iterates' images
    if (options.select_size > 0) mesh_bvh.emplace(mesh);
    auto finish = [&](const std::vector<glm::dvec2>& uv, IterationReport report, Clock::time_point started) {
        if (options.select_size > 0)
            report.image_rms = geometry_image_rms(mesh, *mesh_bvh, uv, options.select_size, options.select_samples);
        report.seconds = seconds_since(started);
        out.iterations.push_back(report);
        if (options.keep_iterates) out.iterates.push_back(uv);
        if (on_iteration) on_iteration(report);
    };

    auto started = Clock::now();
    IterationReport first;
    std::vector<glm::dvec2> uv = solve({}, first);
    std::vector<double> stretch = measure(uv, first);
    finish(uv, first, started);
    out.uv = uv;
    if (!reweighting) {
        close_run();
        return out;
    }
    double best_stretch = first.l2_stretch;
    std::vector<double> returned_weights = weights;  // the weights of out.uv
    // With candidates_size: the start's map and the non-folding iterate of least E_sigma, with their weights.
    struct Candidate {
        std::size_t t = 0;
        std::vector<glm::dvec2> uv;
        std::vector<double> weights;
    };
    Candidate start{0, uv, weights}, least_sigma;
    const bool candidates = options.candidates_size > 0 && options.select_size == 0;
    // With select_size, the iterate of least image error is returned, whatever the variant's rule.
    auto keep = [&](const std::vector<glm::dvec2>& map, std::size_t t) {
        out.uv = map;
        returned_weights = weights;
        out.selected = t;
    };
    for (std::size_t t = 1; t <= options.max_iterations; ++t) {
        // A folded iterate (crushed below what its solve resolves) has no areas to reweight by.
        if (out.iterations.back().flipped > 0) break;
        started = Clock::now();
        IterationReport report;
        report.iteration = t;
        report.sigma_error = options.variant == ParameterizeVariant::Stretch
                                 ? detail::reweigh_by_stretch(in, stretch, weights)
                                 : detail::reweigh_by_density(in, ring_area_2d, weights);
        std::vector<double> flat(2 * n);
        for (std::size_t i = 0; i < n; ++i) flat[2 * i] = uv[i].x, flat[2 * i + 1] = uv[i].y;
        past.push_back(std::move(flat));
        if (past.size() > kPastIterates) past.erase(past.begin());
        try {
            uv = solve(uv, report);
        } catch (const geo::InputError& e) {
            // A system reweighted so far that its solve breaks down (a cut door part's 47th, on
            // lavapipe) ends the run as a fold does: the iterates before it stand.
            out.unsolved = "iteration " + std::to_string(t) + ": " + e.what();
            break;
        }
        stretch = measure(uv, report);
        finish(uv, report, started);
        if (candidates && report.flipped == 0 &&
            (least_sigma.t == 0 || report.sigma_error < out.iterations[least_sigma.t].sigma_error))
            least_sigma = {t, uv, weights};
        if (options.select_size > 0) {
            // A map that folds is never chosen over one that does not, whatever its image.
            const IterationReport &now = out.iterations[t], &held = out.iterations[out.selected];
            if ((now.flipped == 0) != (held.flipped == 0) ? now.flipped == 0 : now.image_rms < held.image_rms)
                keep(uv, t);
        } else if (options.variant == ParameterizeVariant::Stretch) {
            // Yoshizawa et al. keep the map of least L2 stretch.
            if (report.l2_stretch < best_stretch) {
                best_stretch = report.l2_stretch;
                keep(uv, t);
            }
        } else if (report.flipped == 0 || out.iterations[out.selected].flipped > 0) {
            keep(uv, t);
        }
        if (options.variant == ParameterizeVariant::Stretch) {
            // Yoshizawa et al. stop when the L2 stretch stops falling.
            if (!(report.l2_stretch < out.iterations[t - 1].l2_stretch * (1.0 - options.stop_fall))) break;
        } else if (t >= 2) {
            const double before = out.iterations[t - 1].sigma_error;
            const bool rose = report.sigma_error > before;
            if (rose ? options.rise_ends_run : !(report.sigma_error < before * (1.0 - options.stop_fall))) break;
        }
    }
    out.rule_iteration = out.selected;
    if (candidates && out.selected > 0) {
        const geo::TriangleBvh bvh(mesh);
        auto measure_image = [&](std::size_t t, const std::vector<glm::dvec2>& map) {
            out.iterations[t].image_rms =
                geometry_image_rms(mesh, bvh, map, options.candidates_size, kCandidateSamples);
            return out.iterations[t].image_rms;
        };
        double best = measure_image(out.selected, out.uv);
        for (Candidate* c : {&start, &least_sigma}) {
            if (c->uv.empty() || c->t == out.selected || measure_image(c->t, c->uv) >= best) continue;
            best = out.iterations[c->t].image_rms;
            out.uv = c->uv;
            returned_weights = c->weights;
            out.selected = c->t;
        }
    }
    if (iterate_tolerance > options.solve_tolerance) {
        weights = std::move(returned_weights);
        out.uv = solve_to(out.uv, options.solve_tolerance, out.final_solver_iterations);
    }
    close_run();
    return out;
}

}  // namespace gimg::passes

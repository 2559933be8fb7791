// Gu, Wang, Chan, Thompson and Yau (2004) as chapter 3 of the Kanai paper gives it: the CPU
// reference. Gauss map, then gradient descent of the Tutte energy (uniform weights), then of the
// conformal energy (cotangent weights of the original mesh) with mass-centre normalisation, every
// vertex moved at once by the user's step constants c_t and c_c. It diverges when a step is too
// large and folds when one is too small (the paper's table 1); both are reported, never hidden.
#include "gimg/passes/sphere.h"

#include "sphere/weighted_graph.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace gimg::passes {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Gauss map: the unit vertex normal. A vertex whose normals cancel out takes its direction from the
// centroid instead (a unit vector is needed; such vertices are rare and said in the note).
std::vector<glm::dvec3> gauss_map(const geo::Mesh& mesh, std::size_t& fallbacks) {
    std::vector<glm::dvec3> x = geo::vertex_normals(mesh);
    glm::dvec3 centroid(0.0);
    for (const glm::dvec3& p : mesh.positions) centroid += p / double(mesh.vertex_count());
    for (std::size_t v = 0; v < x.size(); ++v) {
        if (glm::dot(x[v], x[v]) > 0.5) continue;
        ++fallbacks;
        const glm::dvec3 d = mesh.positions[v] - centroid;
        x[v] = glm::dot(d, d) > 0.0 ? glm::normalize(d) : glm::dvec3(0.0, 0.0, 1.0);
    }
    return x;
}

enum class PhaseEnd { Converged, IterationLimit, Diverged };

// One gradient-descent phase (Tutte or conformal) on the whole mesh, Jacobi style as in the paper:
// every vertex's step is computed from the same old positions. A phase counts as diverged when the
// energy becomes non-finite or climbs to twice the lowest value seen: descent with a fitting step
// never does that, a too-large step does within a few iterations.
PhaseEnd run_phase(const std::string& name, const detail::WeightedGraph& g, std::vector<glm::dvec3>& x, double step,
                   bool centre, const GuOptions& options, Clock::time_point t0, SphereStage& stage) {
    const auto stage_start = Clock::now();
    std::vector<glm::dvec3> next(x.size());
    double e0 = g.energy(x), lowest = e0;
    stage.name = name;
    stage.vertices = x.size();
    stage.energy = e0;
    PhaseEnd end = PhaseEnd::IterationLimit;
    for (stage.iterations = 0; stage.iterations < options.max_iterations;) {
        for (std::uint32_t v : g.vertices) {
            // D x(v) = L - (L.x) x, L = sum_u w_uv (x(u) - x(v)) (eqs. 6-9).
            glm::dvec3 laplacian(0.0);
            for (std::uint32_t j = g.adjacency.vertex_vertex_offsets[v]; j < g.adjacency.vertex_vertex_offsets[v + 1];
                 ++j)
                laplacian += g.slot_weights[j] * (x[g.adjacency.vertex_vertices[j]] - x[v]);
            const glm::dvec3 tangential = laplacian - glm::dot(laplacian, x[v]) * x[v];
            next[v] = glm::normalize(x[v] + step * tangential);  // eqs. 4, 5 and back onto the sphere
        }
        if (centre) {
            // The mass centre is the mean of the points: the paper writes the plain sum, which would
            // throw every point to the antipode of the sum as soon as it is longer than 1.
            glm::dvec3 c(0.0);
            for (std::uint32_t v : g.vertices) c += next[v];
            c /= double(g.vertices.size());
            for (std::uint32_t v : g.vertices) next[v] = glm::normalize(next[v] - c);
        }
        ++stage.iterations;
        const double e = g.energy(next);
        if (!std::isfinite(e) || e > 2.0 * lowest) {
            end = PhaseEnd::Diverged;
            stage.energy = e;
            break;  // x keeps the last finite iterate
        }
        x.swap(next);
        stage.energy = e;
        lowest = std::min(lowest, e);
        if (options.progress && stage.iterations % 500 == 0)
            options.progress(name, stage.iterations, e, detail::count_flips(g.triangles, x), seconds_since(t0));
        if (std::abs(e - e0) < options.tolerance) {
            end = PhaseEnd::Converged;
            break;
        }
        e0 = e;
    }
    stage.seconds = seconds_since(stage_start);
    return end;
}

std::string describe(const SphereStage& s, PhaseEnd end, double step) {
    char buf[200];
    if (end == PhaseEnd::Diverged)
        std::snprintf(buf, sizeof buf, "%s phase diverged after %zu iterations (energy %.6g; step %g is too large)",
                      s.name.c_str(), s.iterations, s.energy, step);
    else
        std::snprintf(buf, sizeof buf, "%s phase stopped at the iteration limit (%zu) with energy %.6g", s.name.c_str(),
                      s.iterations, s.energy);
    return buf;
}

}  // namespace

SphereResult sphere_gu(const geo::Mesh& mesh, const GuOptions& options) {
    check_sphere_input(mesh);
    for (double c : {options.tutte_step, options.conformal_step, options.tolerance})
        if (!(c > 0.0) || !std::isfinite(c))
            throw geo::InputError("gu: step constants and tolerance must be positive numbers");
    const auto t0 = Clock::now();
    SphereResult result;
    std::vector<std::string> notes;
    std::size_t fallbacks = 0;
    result.positions = gauss_map(mesh, fallbacks);
    if (fallbacks)
        notes.push_back(std::to_string(fallbacks) +
                        " vertices had no normal and started from the centroid's direction");

    const detail::WeightedGraph tutte = detail::make_weighted_graph(mesh, mesh.triangles, detail::EdgeWeights::Uniform);
    SphereStage stage;
    PhaseEnd end = run_phase("tutte", tutte, result.positions, options.tutte_step, false, options, t0, stage);
    result.stages.push_back(stage);
    if (end == PhaseEnd::Converged) {
        const detail::WeightedGraph conformal =
            detail::make_weighted_graph(mesh, mesh.triangles, detail::EdgeWeights::Cotangent);
        end = run_phase("conformal", conformal, result.positions, options.conformal_step, true, options, t0, stage);
        result.stages.push_back(stage);
    }
    if (end != PhaseEnd::Converged) {
        result.converged = false;
        notes.push_back(describe(stage, end, stage.name == "tutte" ? options.tutte_step : options.conformal_step));
    }
    const std::size_t flips = detail::count_flips(mesh.triangles, result.positions);
    if (flips) notes.push_back(std::to_string(flips) + " flipped triangles (the map is not one-to-one)");
    for (const std::string& n : notes) result.note += (result.note.empty() ? "" : "; ") + n;
    if (options.progress) options.progress("done", stage.iterations, stage.energy, flips, seconds_since(t0));
    return result;
}

}  // namespace gimg::passes

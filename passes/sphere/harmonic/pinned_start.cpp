// Choi, Lam and Lui's north-pole step on the GPU: the direct route's start.
#include "sphere/harmonic/pinned_start.h"

#include "sphere/linear/plane_harmonic_map.h"
#include "sphere/linear/stereographic.h"
#include "solvers/conjugate_gradients.h"
#include "solvers/multigrid.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <complex>

namespace gimg::passes::detail {

namespace {

// The start's conjugate gradients, checked first after so many iterations, at most so many: the
// multigrid preconditioner reaches the start's 1e-5 in 6-7 (armadillo, armadillo_loop1, bunny,
// cow, dino), where a first check after 8 overshot to 1e-6 - 1e-7.
constexpr std::uint32_t kIterationsPerCheck = 6;
constexpr std::size_t kMaxIterations = 2000;

}  // namespace

PinnedStart pinned_start_gpu(Context& ctx, const geo::Mesh& mesh, const RelaxationMesh& level, double tolerance,
                             bool timestamps, const std::function<void(std::size_t, double)>& progress,
                             const std::function<void()>& before_gpu) {
    PinnedStart start;
    const std::size_t n = mesh.vertex_count();
    const std::uint32_t big = linear_sphere::most_regular_face(mesh);
    const glm::uvec3 t = mesh.triangles[big];
    const auto flat = linear_sphere::flat_big_triangle(mesh, big);
    std::vector<std::uint8_t> pinned(n, 0);
    std::vector<glm::dvec2> chart(n, glm::dvec2(0.0));  // the free vertices start at the origin
    for (int k = 0; k < 3; ++k) {
        pinned[t[k]] = 1;
        chart[t[k]] = {flat[std::size_t(k)].real(), flat[std::size_t(k)].imag()};
    }
    const ChartProblem problem = make_dirichlet_problem(level, pinned, chart);
    start.free_vertices = problem.rows();
    if (std::any_of(problem.diagonal.begin(), problem.diagonal.end(), [](double d) { return !(d > 0.0); })) {
        start.why = "a vertex's cotangent weights sum to zero or less";
        return start;
    }
    Multigrid mg;
    try {
        mg = build_multigrid(problem);
    } catch (const geo::InputError& e) {
        start.why = e.what();
        return start;
    }
    if (before_gpu) before_gpu();
    const CgSolve solve =
        solve_cg_gpu(ctx, problem, mg, tolerance, kIterationsPerCheck, kMaxIterations, timestamps, progress);
    start.iterations = solve.iterations;
    start.residual = solve.residual;
    start.gpu_ms = solve.gpu_ms;
    if (!std::isfinite(solve.residual)) {
        start.why = "conjugate gradients broke down (the problem or its preconditioner is not positive definite)";
        return start;
    }
    if (!solve.converged(tolerance)) {
        start.why = "conjugate gradients stopped at residual " + std::to_string(solve.residual);
        return start;
    }

    // The plane map, centred on the vertices' mean as in sphere_linear, balanced and projected.
    std::vector<std::complex<double>> z(n);
    for (std::uint32_t v = 0; v < n; ++v) z[v] = {chart[v].x, chart[v].y};
    for (std::size_t i = 0; i < problem.rows(); ++i) z[problem.free_vertices[i]] = {solve.x[i].x, solve.x[i].y};
    std::complex<double> mean(0.0, 0.0);
    for (const auto& w : z) mean += w;
    mean /= double(n);
    for (auto& w : z) w -= mean;
    const double scale = linear_sphere::balancing_scale(mesh, z, big);
    start.y.resize(n);
    for (std::uint32_t v = 0; v < n; ++v)
        start.y[v] = glm::normalize(linear_sphere::sphere_from_south_chart(scale * z[v]));

    // The polish's pole: inside the face nearest the origin (never on a vertex, whose chart point
    // would be infinite).
    const std::size_t inner = linear_sphere::face_nearest_origin(mesh, z, big);
    if (inner < mesh.face_count()) {
        const glm::uvec3 s = mesh.triangles[inner];
        start.accurate_pole = glm::normalize(start.y[s.x] + start.y[s.y] + start.y[s.z]);
    }
    const bool finite = std::all_of(start.y.begin(), start.y.end(), [](const glm::dvec3& p) {
        return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    });
    if (!finite) start.why = "the harmonic map has points that are not finite";
    return start;
}

double total_solid_angle(const RelaxationMesh& level, const std::vector<glm::dvec3>& y) {
    // In chunks on the CPU's threads, summed in chunk order (relaxation_mesh.h).
    const std::size_t n = level.vertex_count();
    std::vector<double> sums(geo::chunk_count(n, kLevelChunk), 0.0);
    geo::parallel_for_chunks(n, kLevelChunk, [&](std::size_t chunk, std::size_t first, std::size_t end) {
        double sum = 0.0;
        for (auto v = std::uint32_t(first); v < end; ++v) {
            const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
            for (std::uint32_t k = 0; k < degree; ++k) {
                const std::uint32_t a = level.ring[begin + k], b = level.ring[begin + (k + 1) % degree];
                if (a < v || b < v) continue;  // each triangle once, from its smallest vertex
                // Van Oosterom and Strackee's solid angle of the spherical triangle (v, a, b).
                const glm::dvec3 p = y[v], q = y[a], r = y[b];
                sum += 2.0 * std::atan2(glm::dot(p, glm::cross(q, r)),
                                        1.0 + glm::dot(p, q) + glm::dot(q, r) + glm::dot(r, p));
            }
        }
        sums[chunk] = sum;
    });
    double total = 0.0;
    for (double sum : sums) total += sum;
    return total;
}

}  // namespace gimg::passes::detail

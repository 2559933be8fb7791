// The region's map: boundary values by chord length, Floater's or chord-length weights, a flat,
// accelerated or over-relaxed start, and one of three solvers (the paper's relaxation, BiCGSTAB,
// SparseLU).
#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/quad_region.h"
#include "gimg/passes/solvers.h"
#include "parameterize/tutte_system.h"
#include "quad_region/relaxation.h"

#include <Eigen/SparseLU>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>

namespace gimg::passes {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

std::vector<glm::dvec2> solve_direct(const LinearSystem& s) {
    const auto n = Eigen::Index(s.a.size);
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
    for (std::size_t i = 0; i < s.a.size; ++i) {
        if (s.fixed[i]) {
            entries.emplace_back(int(i), int(i), 1.0);
            rhs(Eigen::Index(i), 0) = s.fixed_values[2 * i], rhs(Eigen::Index(i), 1) = s.fixed_values[2 * i + 1];
            continue;
        }
        for (std::uint32_t k = s.a.offsets[i]; k < s.a.offsets[i + 1]; ++k)
            entries.emplace_back(int(i), int(s.a.columns[k]), s.a.values[k]);
    }
    Eigen::SparseMatrix<double> a(n, n);
    a.setFromTriplets(entries.begin(), entries.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(a);
    if (lu.info() != Eigen::Success) throw geo::InputError("the region's system is singular");
    const Eigen::MatrixXd x = lu.solve(rhs);
    std::vector<glm::dvec2> uv(s.a.size);
    for (std::size_t i = 0; i < uv.size(); ++i) uv[i] = {x(Eigen::Index(i), 0), x(Eigen::Index(i), 1)};
    return uv;
}

// Eq. (2) for u and v: on the GPU one after the other, on the CPU one a core (independent systems).
std::array<std::size_t, 2> relax_both(Context* ctx, const detail::ColouredRows& rows, double k, double tau,
                                      std::size_t max_sweeps, std::vector<glm::dvec2>& uv) {
    std::array<std::size_t, 2> sweeps{};
    if (ctx) {
        sweeps = detail::relax_gpu(*ctx, rows, k, tau, max_sweeps, uv);
    } else {
        geo::parallel_for_chunks(2, 1, [&](std::size_t field, std::size_t, std::size_t) {
            sweeps[field] = detail::relax_cpu(rows, k, tau, max_sweeps, uv, int(field));
        });
    }
    return sweeps;
}

}  // namespace

std::vector<double> chord_weights(const geo::Mesh& mesh, const geo::MeshAdjacency& adj) {
    std::vector<double> w(adj.vertex_vertices.size(), 0.0);
    const std::vector<std::uint8_t> interior = adj.interior_vertices();
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        if (!interior[i]) continue;
        const auto nb = adj.neighbors(i);
        double sum = 0.0;
        for (std::size_t j = 0; j < nb.size(); ++j)
            sum += w[adj.vertex_vertex_offsets[i] + j] = 1.0 / glm::distance(mesh.positions[i], mesh.positions[nb[j]]);
        for (std::size_t j = 0; j < nb.size(); ++j) w[adj.vertex_vertex_offsets[i] + j] /= sum;
    }
    return w;
}

QuadMap map_quad_region(Context* ctx, const QuadRegion& region, const QuadMapOptions& o,
                        const std::vector<glm::dvec2>& warm) {
    if (region.corner_count != 4) throw geo::InputError("a square map needs a region of four corners");
    if (!(o.relaxation >= 0.0 && o.relaxation < 1.0)) throw geo::InputError("the relaxation k must be in [0, 1)");
    if (!(o.tau > 0.0)) throw geo::InputError("tau must be positive");
    const geo::Mesh& mesh = region.mesh;
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const SquareBoundary boundary = square_boundary(mesh, adj, region.corners);
    const std::size_t n = mesh.vertex_count();
    std::vector<std::uint8_t> interior(n, 1);
    std::vector<glm::dvec2> fixed(n, glm::dvec2(0.5));
    for (std::size_t k = 0; k < boundary.loop.size(); ++k) {
        interior[boundary.loop[k]] = 0;
        fixed[boundary.loop[k]] = boundary.uv[k];
    }
    QuadMap out;
    auto t = Clock::now();
    const std::vector<double> w = o.weights == QuadWeights::Floater
                                      ? floater_weights(mesh, adj, interior, &out.weight_fallbacks)
                                      : chord_weights(mesh, adj);
    out.weights_ms = ms_since(t);

    t = Clock::now();
    out.start = fixed;  // flat: 0.5 on every free vertex
    if (o.start != QuadStart::Flat)
        out.start_sweeps = dijkstra_start(region, adj, fixed, o.relaxation, o.tau, out.start, &out.start_folded);
    out.accelerated = out.start;
    if (warm.size() == n)
        for (std::size_t i = 0; i < n; ++i)
            if (interior[i] && !std::isnan(warm[i].x)) out.start[i] += warm[i];
    std::optional<detail::ColouredRows> rows;
    if (o.start == QuadStart::Overrelaxed || o.solver == QuadSolver::Iterate)
        rows = detail::colour_rows(adj, w, interior);
    if (o.start == QuadStart::Overrelaxed) {
        std::vector<glm::dvec2> over = out.start;
        relax_both(ctx, *rows, 1.0 - kOverrelaxation, 0.0, kOverrelaxedSweeps, over);
        // The map lies in the square (positive weights summing to 1); sweeps that left it far
        // behind diverged on this mesh, and the accelerated start stands.
        const bool settled = std::all_of(over.begin(), over.end(), [](glm::dvec2 p) {
            return p.x >= -0.5 && p.x <= 1.5 && p.y >= -0.5 && p.y <= 1.5;
        });
        if (settled) out.start = std::move(over), out.overrelaxed_sweeps = kOverrelaxedSweeps;
    }
    out.start_ms = ms_since(t);

    t = Clock::now();
    out.uv = out.start;
    switch (o.solver) {
        case QuadSolver::Iterate: {
            const auto sweeps = relax_both(ctx, *rows, o.relaxation, o.tau, o.max_sweeps, out.uv);
            out.iterations_u = sweeps[0], out.iterations_v = sweeps[1];
            break;
        }
        case QuadSolver::Krylov: {
            const LinearSystem s = detail::tutte_system(adj, w, interior, fixed, out.start);
            // The V-cycle of the system's symmetric part: a tenth of Jacobi's iterations.
            const SolveOptions so{.tolerance = o.krylov_tolerance,
                                  .max_iterations = 20000,
                                  .iterations_per_check = 4,
                                  .preconditioner = Preconditioner::Multigrid};
            const SolveResult r = ctx ? solve_general(*ctx, s, so) : solve_general_cpu(s, so);
            if (!r.converged) throw geo::InputError("the region's system did not converge");
            for (std::size_t i = 0; i < n; ++i) out.uv[i] = {r.x[2 * i], r.x[2 * i + 1]};
            out.iterations_u = out.iterations_v = r.iterations;
            break;
        }
        case QuadSolver::Direct:
            out.uv = solve_direct(detail::tutte_system(adj, w, interior, fixed, {}));
            break;
    }
    out.solve_ms = ms_since(t);
    out.flipped = count_flipped(mesh, out.uv);
    return out;
}

std::vector<glm::dvec3> barycentric_map(Context* ctx, const QuadRegion& r, QuadWeights weights) {
    if (r.corner_count != 3) throw geo::InputError("barycentric coordinates need a region of three corners");
    const geo::Mesh& mesh = r.mesh;
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const std::vector<double> w =
        weights == QuadWeights::Floater ? floater_weights(mesh, adj) : chord_weights(mesh, adj);
    const std::size_t n = mesh.vertex_count();
    // Boundary values: walk each side W_i -> W_i+1 by chord length; coordinate i falls from 1 to 0
    // along it, coordinate i+1 rises from 0 to 1, the third is 0.
    std::vector<glm::dvec3> fixed(n, glm::dvec3(0.0));
    const SquareBoundary loop = square_boundary(mesh, adj, std::nullopt);  // the boundary loop, any corners
    std::vector<std::uint32_t> order = loop.loop;
    std::rotate(order.begin(), std::find(order.begin(), order.end(), r.corners[0]), order.end());
    for (int i = 0; i < 3; ++i) {
        const auto begin = std::find(order.begin(), order.end(), r.corners[i]);
        const auto end = i < 2 ? std::find(order.begin(), order.end(), r.corners[i + 1]) : order.end();
        std::vector<std::uint32_t> side(begin, end);
        side.push_back(i < 2 ? *end : order.front());
        double total = 0.0;
        std::vector<double> arc{0.0};
        for (std::size_t k = 0; k + 1 < side.size(); ++k)
            arc.push_back(total += glm::distance(mesh.positions[side[k]], mesh.positions[side[k + 1]]));
        for (std::size_t k = 0; k + 1 < side.size(); ++k) {
            const double t = total > 0.0 ? arc[k] / total : 0.0;
            fixed[side[k]][i] = 1.0 - t;
            fixed[side[k]][(i + 1) % 3] = t;
        }
    }
    LinearSystem s;
    s.a.size = n;
    s.rhs_count = 3;
    std::vector<std::uint8_t> boundary(n, 0);
    for (std::uint32_t v : order) boundary[v] = 1;
    for (std::size_t i = 0; i < n; ++i) {
        s.a.columns.push_back(std::uint32_t(i));
        s.a.values.push_back(1.0);
        if (!boundary[i]) {
            const auto nb = adj.neighbors(i);
            for (std::size_t k = 0; k < nb.size(); ++k)
                s.a.columns.push_back(nb[k]), s.a.values.push_back(-w[adj.vertex_vertex_offsets[i] + k]);
        }
        s.a.offsets.push_back(std::uint32_t(s.a.columns.size()));
    }
    s.b.assign(3 * n, 0.0);
    s.fixed = boundary;
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) s.fixed_values.push_back(fixed[i][c]);
    std::vector<glm::dvec3> out(n);
    if (ctx) {
        const SolveResult res = solve_general(
            *ctx, s, {.tolerance = 1e-12, .max_iterations = 20000, .preconditioner = Preconditioner::Multigrid});
        if (!res.converged) throw geo::InputError("the barycentric system did not converge");
        for (std::size_t i = 0; i < n; ++i) out[i] = {res.x[3 * i], res.x[3 * i + 1], res.x[3 * i + 2]};
    } else {
        // Two direct solves of the two-column helper, the third column from the first's matrix.
        LinearSystem first = s, second = s;
        first.rhs_count = second.rhs_count = 2;
        first.fixed_values.clear(), second.fixed_values.clear();
        for (std::size_t i = 0; i < n; ++i) {
            first.fixed_values.insert(first.fixed_values.end(), {fixed[i].x, fixed[i].y});
            second.fixed_values.insert(second.fixed_values.end(), {fixed[i].z, 0.0});
        }
        first.b.assign(2 * n, 0.0), second.b.assign(2 * n, 0.0);
        const std::vector<glm::dvec2> xy = solve_direct(first), z = solve_direct(second);
        for (std::size_t i = 0; i < n; ++i) out[i] = {xy[i].x, xy[i].y, z[i].x};
    }
    for (auto& b : out) b /= b.x + b.y + b.z;
    return out;
}

}  // namespace gimg::passes

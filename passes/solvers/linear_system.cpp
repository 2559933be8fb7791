// The public sparse solvers (gimg/passes/solvers.h): the input checked, the Dirichlet rows moved to
// the right-hand side, the right-hand sides solved in pairs, the fixed rows put back.
#include "gimg/passes/solvers.h"

#include "solvers/bicgstab.h"
#include "solvers/conjugate_gradients.h"
#include "solvers/multigrid.h"
#include "solvers/vcycle.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

namespace gimg::passes {

namespace {

using detail::CsrMatrix;

}  // namespace

struct PreconditionerCache::Hierarchy {
    detail::Multigrid multigrid;
    // The hierarchy uploaded for solve_general on `cycle_context`: a real GPU waits for each upload
    // (nine textures for two levels), so a run of solves uploads it once.
    std::unique_ptr<detail::GpuVcycle> cycle;
    const Context* cycle_context = nullptr;
};
PreconditionerCache::PreconditionerCache() = default;
PreconditionerCache::~PreconditionerCache() = default;
void PreconditionerCache::clear() { hierarchy.reset(); }

namespace {

// What is left of the system on its free rows, with one right-hand side per column.
struct FreeSystem {
    std::vector<std::uint32_t> free_rows;  // free row i is row free_rows[i]
    CsrMatrix a;                           // every entry between free rows, diagonal included
    std::vector<double> diagonal;
    std::vector<double> fixed_coupling;           // per free row, |a_ij| summed over its fixed columns
    std::vector<std::vector<double>> rhs, start;  // per right-hand side, one per free row
};

double at(const std::vector<double>& v, std::size_t i) { return v.empty() ? 0.0 : v[i]; }

void check_system(const LinearSystem& s) {
    const SparseMatrix& a = s.a;
    const std::size_t n = a.size, k = s.rhs_count;
    if (k < 1 || k > 4)
        throw geo::InputError("linear system: " + std::to_string(k) + " right-hand sides (1 to 4 allowed)");
    if (a.offsets.size() != n + 1 || a.offsets.front() != 0 || a.columns.size() != a.values.size() ||
        a.offsets.back() != a.columns.size())
        throw geo::InputError("linear system: the matrix's compressed rows do not match its size " + std::to_string(n));
    for (std::size_t i = 0; i < n; ++i)
        if (a.offsets[i] > a.offsets[i + 1])
            throw geo::InputError("linear system: row " + std::to_string(i) + " ends before it begins");
    for (std::size_t e = 0; e < a.columns.size(); ++e) {
        if (a.columns[e] >= n)
            throw geo::InputError("linear system: column " + std::to_string(a.columns[e]) + " out of range (size " +
                                  std::to_string(n) + ")");
        if (!std::isfinite(a.values[e])) throw geo::InputError("linear system: a matrix entry is not finite");
    }
    auto check_vector = [&](const std::vector<double>& v, const char* name, bool optional) {
        if (optional && v.empty()) return;
        if (v.size() != n * k)
            throw geo::InputError(std::string("linear system: ") + name + " has " + std::to_string(v.size()) +
                                  " values, not " + std::to_string(n * k));
        for (double x : v)
            if (!std::isfinite(x)) throw geo::InputError(std::string("linear system: ") + name + " is not finite");
    };
    check_vector(s.b, "b", false);
    check_vector(s.fixed_values, "fixed_values", true);
    check_vector(s.start, "start", true);
    if (!s.fixed.empty() && s.fixed.size() != n)
        throw geo::InputError("linear system: fixed has " + std::to_string(s.fixed.size()) + " entries, not " +
                              std::to_string(n));
}

FreeSystem free_system(const LinearSystem& s) {
    check_system(s);
    const std::size_t n = s.a.size, k = s.rhs_count;
    FreeSystem f;
    std::vector<std::uint32_t> index(n, UINT32_MAX);
    for (std::uint32_t i = 0; i < n; ++i)
        if (s.fixed.empty() || !s.fixed[i]) {
            index[i] = std::uint32_t(f.free_rows.size());
            f.free_rows.push_back(i);
        }
    const std::size_t m = f.free_rows.size();
    f.a.cols = m;
    f.diagonal.assign(m, 0.0);
    f.fixed_coupling.assign(m, 0.0);
    f.rhs.assign(k, std::vector<double>(m, 0.0));
    f.start.assign(k, std::vector<double>(m, 0.0));
    for (std::size_t fi = 0; fi < m; ++fi) {
        const std::uint32_t i = f.free_rows[fi];
        for (std::size_t c = 0; c < k; ++c) {
            f.rhs[c][fi] = s.b[i * k + c];
            f.start[c][fi] = at(s.start, i * k + c);
        }
        for (std::uint32_t e = s.a.offsets[i]; e < s.a.offsets[i + 1]; ++e) {
            const std::uint32_t j = s.a.columns[e];
            const double value = s.a.values[e];
            if (index[j] == UINT32_MAX) {  // a fixed column: its known value moves to the right-hand side
                for (std::size_t c = 0; c < k; ++c) f.rhs[c][fi] -= value * at(s.fixed_values, j * k + c);
                f.fixed_coupling[fi] += std::abs(value);
                continue;
            }
            if (j == i) f.diagonal[fi] += value;
            f.a.columns.push_back(index[j]);
            f.a.values.push_back(value);
        }
        f.a.offsets.push_back(std::uint32_t(f.a.columns.size()));
        if (!(f.diagonal[fi] != 0.0))
            throw geo::InputError("linear system: row " + std::to_string(i) + " is free but its diagonal entry is 0");
    }
    return f;
}

// The symmetric positive definite part of the conjugate gradients' input for the pair of
// right-hand sides starting at column c0 (the second zero when there is none).
detail::SpdSystem spd_pair(const FreeSystem& f, std::size_t c0) {
    detail::SpdSystem sys;
    const std::size_t m = f.free_rows.size();
    sys.diagonal = f.diagonal;
    sys.row_offsets.push_back(0);
    for (std::size_t i = 0; i < m; ++i) {
        for (std::uint32_t e = f.a.offsets[i]; e < f.a.offsets[i + 1]; ++e)
            if (f.a.columns[e] != i) {
                sys.columns.push_back(f.a.columns[e]);
                sys.values.push_back(f.a.values[e]);
            }
        sys.row_offsets.push_back(std::uint32_t(sys.columns.size()));
    }
    const bool second = c0 + 1 < f.rhs.size();
    sys.rhs.resize(m);
    sys.start.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
        sys.rhs[i] = {f.rhs[c0][i], second ? f.rhs[c0 + 1][i] : 0.0};
        sys.start[i] = {f.start[c0][i], second ? f.start[c0 + 1][i] : 0.0};
    }
    return sys;
}

void check_symmetric(const FreeSystem& f) {
    // Entry (i, j) against (j, i), both rows sorted by column.
    const std::size_t m = f.free_rows.size();
    std::vector<std::vector<std::pair<std::uint32_t, double>>> rows(m);
    for (std::size_t i = 0; i < m; ++i) {
        for (std::uint32_t e = f.a.offsets[i]; e < f.a.offsets[i + 1]; ++e)
            rows[i].emplace_back(f.a.columns[e], f.a.values[e]);
        std::sort(rows[i].begin(), rows[i].end());
    }
    auto entry = [&](std::size_t i, std::uint32_t j) {
        auto it = std::lower_bound(rows[i].begin(), rows[i].end(),
                                   std::make_pair(j, -std::numeric_limits<double>::infinity()));
        return it != rows[i].end() && it->first == j ? it->second : 0.0;
    };
    for (std::size_t i = 0; i < m; ++i)
        for (const auto& [j, value] : rows[i]) {
            const double other = entry(j, std::uint32_t(i));
            const double scale = std::sqrt(std::abs(f.diagonal[i] * f.diagonal[j]));
            if (std::abs(value - other) > 1e-12 * std::max(scale, std::abs(value)))
                throw geo::InputError("linear system: the matrix is not symmetric (entry " +
                                      std::to_string(f.free_rows[i]) + ", " + std::to_string(f.free_rows[j]) +
                                      "): use solve_general");
        }
    for (std::size_t i = 0; i < m; ++i)
        if (!(f.diagonal[i] > 0.0))
            throw geo::InputError("linear system: row " + std::to_string(f.free_rows[i]) +
                                  " has a diagonal entry <= 0: the matrix is not positive definite");
}

SolveResult assemble(const LinearSystem& s, const FreeSystem& f, const std::vector<std::vector<double>>& x) {
    const std::size_t n = s.a.size, k = s.rhs_count;
    SolveResult r;
    r.x.assign(n * k, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        if (!s.fixed.empty() && s.fixed[i])
            for (std::size_t c = 0; c < k; ++c) r.x[i * k + c] = at(s.fixed_values, i * k + c);
    for (std::size_t fi = 0; fi < f.free_rows.size(); ++fi)
        for (std::size_t c = 0; c < k; ++c) r.x[f.free_rows[fi] * k + c] = x[c][fi];
    return r;
}

void breakdown(const std::string& method, const std::string& what) {
    throw geo::InputError("linear system: " + method + " broke down (" + what + ")");
}

// Conjugate gradients on every pair, on the GPU or the CPU twin, with the same checks.
template <class RunPair>
SolveResult solve_symmetric_with(const LinearSystem& s, const SolveOptions& o, RunPair run_pair) {
    const FreeSystem f = free_system(s);
    check_symmetric(f);
    std::vector<std::vector<double>> x(s.rhs_count, std::vector<double>(f.free_rows.size(), 0.0));
    std::size_t iterations = 0;
    double residual = 0.0;
    if (!f.free_rows.empty()) {
        detail::SpdSystem first = spd_pair(f, 0);
        const detail::Multigrid mg = detail::build_multigrid(first);
        for (std::size_t c0 = 0; c0 < s.rhs_count; c0 += 2) {
            const detail::SpdSystem sys = c0 == 0 ? std::move(first) : spd_pair(f, c0);
            const detail::CgSolve solve = run_pair(sys, mg);
            if (std::isnan(solve.residual))
                breakdown("conjugate gradients", "r.z < 0: the matrix or its preconditioner is not positive definite");
            iterations = std::max(iterations, solve.iterations);
            residual = std::max(residual, solve.residual);
            for (std::size_t i = 0; i < f.free_rows.size(); ++i) {
                x[c0][i] = solve.x[i].x;
                if (c0 + 1 < s.rhs_count) x[c0 + 1][i] = solve.x[i].y;
            }
        }
    }
    SolveResult r = assemble(s, f, x);
    r.iterations = iterations;
    r.residual = residual;
    r.converged = residual <= o.tolerance;
    return r;
}

// |r| / |b| per right-hand side of a pair, the larger (a zero b counts |r|).
double pair_residual(glm::dvec2 rr, glm::dvec2 bb, bool second) {
    auto rel = [](double r2, double b2) { return b2 > 0.0 ? std::sqrt(r2 / b2) : std::sqrt(r2); };
    return second ? std::max(rel(rr.x, bb.x), rel(rr.y, bb.y)) : rel(rr.x, bb.x);
}

// BiCGSTAB near breakdown: on a right-hand side not yet converged, r0 . r under 1e-12 of |r0| |r|
// (the solves that converge stay above 5e-10; a stalled one fell to 1e-15 and below).
constexpr std::size_t kMaxRestarts = 5;
bool shadow_orthogonal(glm::dvec2 r0r0, glm::dvec2 r0r, glm::dvec2 rr, glm::dvec2 bb, double tolerance, bool second) {
    auto stalled = [&](double r0_r0, double r0_r, double r_r, double b_b) {
        const double rel = b_b > 0.0 ? std::sqrt(r_r / b_b) : std::sqrt(r_r);
        return rel > tolerance && std::abs(r0_r) <= 1e-12 * std::sqrt(r0_r0 * r_r);
    };
    return stalled(r0r0.x, r0r.x, rr.x, bb.x) || (second && stalled(r0r0.y, r0r.y, rr.y, bb.y));
}

template <class Solver>
SolveResult solve_general_with(const LinearSystem& s, const SolveOptions& o, Solver make_solver) {
    const FreeSystem f = free_system(s);
    const std::size_t m = f.free_rows.size();
    std::vector<std::vector<double>> x(s.rhs_count, std::vector<double>(m, 0.0));
    std::size_t iterations = 0;
    double residual = 0.0;
    const CsrMatrix& a = f.a;
    // The multigrid preconditioner's hierarchy, shared by every pair; Jacobi where aggregation
    // stalls (a matrix with almost no off-diagonal entries, which Jacobi solves well anyway).
    std::optional<detail::Multigrid> built;
    const detail::Multigrid* mg = nullptr;
    if (o.preconditioner == Preconditioner::Multigrid && m > 0) {
        PreconditionerCache::Hierarchy* cached = o.reuse ? o.reuse->hierarchy.get() : nullptr;
        if (cached && cached->multigrid.rows() == m) {
            mg = &cached->multigrid;
        } else {
            try {
                built = detail::build_multigrid(detail::symmetric_laplacian(a, f.fixed_coupling));
                mg = &*built;
                if (o.reuse) {
                    o.reuse->hierarchy = std::make_unique<PreconditionerCache::Hierarchy>(std::move(*built));
                    mg = &o.reuse->hierarchy->multigrid;
                }
            } catch (const geo::InputError&) {
                mg = nullptr;
            }
        }
    }
    for (std::size_t c0 = 0; c0 < s.rhs_count && m > 0; c0 += 2) {
        const bool second = c0 + 1 < s.rhs_count;
        std::vector<glm::dvec2> b(m), x0(m);
        glm::dvec2 bb(0.0);
        for (std::size_t i = 0; i < m; ++i) {
            b[i] = {f.rhs[c0][i], second ? f.rhs[c0 + 1][i] : 0.0};
            x0[i] = {f.start[c0][i], second ? f.start[c0 + 1][i] : 0.0};
            bb += b[i] * b[i];
        }
        detail::BicgState start = detail::start_bicgstab(a, b, x0);
        using Run = decltype(make_solver(a, start, mg));
        auto solver = std::make_unique<Run>(make_solver(a, start, mg));
        double res = pair_residual(start.rr, bb, second);
        std::size_t it = 0, restarts = 0;
        // Checked after per_check iterations, then after as many as the last check's rate needs.
        const std::uint32_t per_check = std::max<std::uint32_t>(o.iterations_per_check, 1);
        std::uint32_t next = per_check;
        while (it < o.max_iterations && res > o.tolerance) {
            const std::uint32_t chunk = std::uint32_t(std::min<std::size_t>(next, o.max_iterations - it));
            const auto [r0r, rr] = solver->run(chunk);
            it += chunk;
            const double before = res;
            res = pair_residual(rr, bb, second);
            next = detail::iterations_to_reach(o.tolerance, before, res, chunk, per_check);
            if (!std::isfinite(res)) breakdown("BiCGSTAB", "the residual is not finite");
            if (res > o.tolerance && shadow_orthogonal(start.rr, r0r, rr, bb, o.tolerance, second)) {
                // r has turned orthogonal to the shadow residual r0 and BiCGSTAB stalls (a cut plant's
                // reweighted system on lavapipe: 2,100 iterations at 5e-5): start again from here.
                if (++restarts > kMaxRestarts)
                    breakdown("BiCGSTAB", "r0 . r = 0 before convergence, after " + std::to_string(kMaxRestarts) +
                                              " restarts: use a direct solver");
                start = detail::start_bicgstab(a, b, solver->solution());
                solver = std::make_unique<Run>(make_solver(a, start, mg));
                next = per_check;
            }
        }
        const std::vector<glm::dvec2> sol = solver->solution();
        for (std::size_t i = 0; i < m; ++i) {
            x[c0][i] = sol[i].x;
            if (second) x[c0 + 1][i] = sol[i].y;
        }
        iterations = std::max(iterations, it);
        residual = std::max(residual, res);
    }
    SolveResult r = assemble(s, f, x);
    r.iterations = iterations;
    r.residual = residual;
    r.converged = residual <= o.tolerance;
    return r;
}

// The CPU twin behind the same interface as GpuBicgstab.
struct CpuBicgstab {
    const CsrMatrix& a;
    detail::BicgState state;
    const detail::Multigrid* mg;
    std::pair<glm::dvec2, glm::dvec2> run(std::uint32_t iterations) {
        detail::bicgstab_cpu(a, state, iterations, mg);
        return {state.r0r, state.rr};
    }
    std::vector<glm::dvec2> solution() const { return state.x; }
};

}  // namespace

SolveResult solve_symmetric(Context& ctx, const LinearSystem& system, const SolveOptions& o) {
    return solve_symmetric_with(system, o, [&](const detail::SpdSystem& sys, const detail::Multigrid& mg) {
        return detail::solve_cg_gpu(ctx, sys, mg, o.tolerance, std::max<std::uint32_t>(o.iterations_per_check, 1),
                                    o.max_iterations, false);
    });
}

SolveResult solve_symmetric_cpu(const LinearSystem& system, const SolveOptions& o) {
    return solve_symmetric_with(system, o, [&](const detail::SpdSystem& sys, const detail::Multigrid& mg) {
        detail::CgState state = detail::start_cg(sys, mg);
        detail::CgSolve solve;
        solve.residual = state.relative_residual();
        const std::uint32_t per_check = std::max<std::uint32_t>(o.iterations_per_check, 1);
        std::uint32_t chunk = per_check;
        while (solve.iterations < o.max_iterations && std::isfinite(solve.residual) && solve.residual > o.tolerance) {
            const double before = solve.residual;
            detail::cg_cpu(mg, state, chunk);
            solve.residual = state.relative_residual();
            solve.iterations += chunk;
            chunk = detail::iterations_to_reach(o.tolerance, before, solve.residual, chunk, per_check);
        }
        solve.x = state.x;
        return solve;
    });
}

SolveResult solve_general(Context& ctx, const LinearSystem& system, const SolveOptions& o) {
    return solve_general_with(system, o,
                              [&](const CsrMatrix& a, const detail::BicgState& start, const detail::Multigrid* mg) {
                                  PreconditionerCache::Hierarchy* cached = o.reuse ? o.reuse->hierarchy.get() : nullptr;
                                  if (!mg || !cached || mg != &cached->multigrid)
                                      return detail::GpuBicgstab(ctx, a, start, mg);
                                  if (!cached->cycle || cached->cycle_context != &ctx) {
                                      cached->cycle = std::make_unique<detail::GpuVcycle>(ctx, *mg, "bicgstab mg");
                                      cached->cycle_context = &ctx;
                                  }
                                  return detail::GpuBicgstab(ctx, a, start, *cached->cycle);
                              });
}

SolveResult solve_general_cpu(const LinearSystem& system, const SolveOptions& o) {
    return solve_general_with(system, o,
                              [&](const CsrMatrix& a, const detail::BicgState& start, const detail::Multigrid* mg) {
                                  return CpuBicgstab{a, start, mg};
                              });
}

}  // namespace gimg::passes

#pragma once
// The planar polish, step 2: the conjugate gradient solve of a ChartProblem, preconditioned by one
// multigrid V-cycle (multigrid.h), as iterative compute dispatches (GpuConjugateGradients), and the
// same iterations on the CPU (cg_cpu), which tests compare it with.
//
// One iteration: q = A p and p.q (a pass and a reduction, primitives/reduce_f64, a fixed tree);
// x += alpha p, r -= alpha q; z = V-cycle(r) with r.z from its last pass, and a reduction; then
// p = z + beta p. The scalars alpha and beta never leave the GPU: each pass reads the reduced sums it
// needs. Only r.z comes back, once per call, for the convergence test. (Summing the partials inside
// the next pass instead, to save the reduction dispatches, was 1.3-1.5x slower on lavapipe: its
// workgroup barriers cost more than the dispatches.) Vectors and matrices live in storage images,
// not buffers (matrix_texels.h says why: 2-3x faster on lavapipe).
//
// Number types: x, r, p, q, A and the scalars in double, the V-cycle in float32 (its input r
// rounded to float, its output z widened back). Conjugate gradients only need the preconditioner
// for their search directions; the residual they test is updated in double, so a float cycle
// leaves the solution's precision alone (the protrusions' triangles of area 1e-15 included: the
// cycle sees residuals, which float's exponent range holds at any scale, never positions). A float
// cycle is symmetric only to float's rounding (1e-7), far below what the 1e-5 and 5e-9 tolerances
// of the solves can notice. Its passes gather half the bytes and do float arithmetic:
// armadillo_loop1's cycle took 6.8-7.0 ms an iteration instead of 11.6 on lavapipe (pass
// timestamps), the whole map 0.48 s instead of 0.60, with the same iterations and angles.
#include "solvers/multigrid.h"
#include "solvers/spd_system.h"
#include "solvers/matrix_texels.h"
#include "solvers/vcycle.h"

#include "gimg/engine/context.h"
#include "gimg/engine/plan.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <utility>

namespace gimg::passes::detail {

// |r| / |b| in the preconditioner's norm, from r.z and b.M b. A negative r.z or b.M b means the
// matrix or its preconditioner is not positive definite (cotangent weights can make it so) and
// conjugate gradients have broken down: NaN, never a small number that would pass for converged.
inline double relative_residual(double rz, double rz_rhs) {
    if (rz < 0.0 || rz_rhs < 0.0) return std::nan("");
    return rz_rhs > 0.0 ? std::sqrt(rz / rz_rhs) : 0.0;
}

struct CgState {
    std::vector<glm::dvec2> x, r, p;  // solution, residual b - A x, search direction
    double rz = 0.0;                  // r . z, z = M r (the V-cycle)
    double rz_rhs = 0.0;              // b . M b: the scale rz is measured against
    double relative_residual() const { return detail::relative_residual(rz, rz_rhs); }
};

// x = the problem's start, r = b - A x, p = M r.
CgState start_cg(const SpdSystem& problem, const Multigrid& mg);

// `iterations` conjugate gradient iterations on the CPU, in the GPU's order of operations.
void cg_cpu(const Multigrid& mg, CgState& state, std::uint32_t iterations);

class GpuConjugateGradients {
public:
    // Throws gimg::Error (InvalidArgument) when a vector or matrix is too large for the device's
    // images (matrix_texels.h).
    GpuConjugateGradients(Context& ctx, const SpdSystem& problem, const Multigrid& mg);
    // Runs `iterations` iterations; returns the state's relative residual after them.
    double run(std::uint32_t iterations);
    std::vector<glm::dvec2> solution();
    double start_residual() const { return start_residual_; }  // before the first run
    double last_gpu_ms() const { return last_gpu_ms_; }
    void set_timestamps(bool on) { timestamps_ = on; }

private:
    void upload(const Multigrid& mg, std::future<CgState>& started);
    Plan& plan_for(std::uint32_t iterations);

    Context& ctx_;
    std::uint32_t rows_ = 0;
    double rz_rhs_ = 0.0;
    double start_residual_ = 1.0;
    std::unique_ptr<GpuVcycle> cycle_;
    Image apply_entries_;  // the finest operator's entries in double, for q = A p
    Image apply_rows_;     // its rows when there is no smoothed level (else level 0's)
    Image x_, r_, p_, q_;
    Buffer rz_[2], pq_;  // rz_[rz_index_] holds r.z between calls (each iteration writes the other)
    int rz_index_ = 0;
    bool timestamps_ = false;
    double last_gpu_ms_ = 0.0;
    std::map<std::pair<std::uint32_t, int>, std::unique_ptr<Plan>> plans_;  // by iterations and rz_index_
};

struct CgSolve {
    std::vector<glm::dvec2> x;
    double residual = 1.0;  // relative_residual at the end: NaN when conjugate gradients broke down
    std::size_t iterations = 0;
    double gpu_ms = 0.0;  // pass timestamps, when on
    bool converged(double tolerance) const { return residual <= tolerance; }
};

// The iterations (1 to per_check) until the next check: as many as the rate of the last
// `iterations`, which took the residual from `before` to `after`, needs to reach `tolerance`;
// per_check when the rate says nothing (no progress, or already there). Conjugate gradients
// converge at least as fast as their past rate on these problems, so the guess rarely falls short.
std::uint32_t iterations_to_reach(double tolerance, double before, double after, std::uint32_t iterations,
                                  std::uint32_t per_check);

// GpuConjugateGradients from the problem's start until the relative residual is at most `tolerance`, it
// breaks down, or `max_iterations` are spent; checked after `per_check` iterations, then
// after as many as iterations_to_reach() says (a whole check past the tolerance cost armadillo_loop1
// 4-8 iterations a solve). `progress` (may be empty) hears the iterations and the residual after
// every check.
CgSolve solve_cg_gpu(Context& ctx, const SpdSystem& problem, const Multigrid& mg, double tolerance,
                     std::uint32_t per_check, std::size_t max_iterations, bool timestamps,
                     const std::function<void(std::size_t, double)>& progress = {});

}  // namespace gimg::passes::detail

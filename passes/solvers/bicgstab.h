#pragma once
// BiCGSTAB (van der Vorst 1992), right-preconditioned, for non-symmetric sparse systems, on the
// render graph (GpuBicgstab) and on the CPU in the same order of operations (bicgstab_cpu).
// Right-hand sides come in pairs, each with its own scalars, as dvec2 vectors in texel arrays
// (matrix_texels.h). The preconditioner M is Jacobi (D^-1) or one float32 V-cycle of a multigrid
// hierarchy (vcycle.h), built from symmetric_laplacian(A) for a Tutte-like A: Jacobi's iterations
// grow with the mesh's rings across, the cycle's do not (mannequin_devil's Floater system to 1e-8:
// 408 against 17). One iteration, with y = M p and z = M s:
//   beta = (rho' / rho)(alpha / omega), rho = rho';  p = r + beta (p - omega v);  v = A y;
//   alpha = rho / (r0 . v);  s = r - alpha v;  t = A z;  omega = (t . s) / (t . t);
//   x += alpha y + omega z;  r = s - omega t;  rho' = r0 . r
// The dot products' passes also sum their workgroup's terms, and one workgroup finishes each sum and
// computes the scalar it gives: 8 passes an iteration besides the two V-cycles (on lavapipe a pass
// costs about 0.05 ms however little it does). The scalars stay on the GPU; only r0 . r and r . r
// come back, once per run().
#include "solvers/multigrid.h"
#include "solvers/vcycle.h"

#include "gimg/engine/context.h"
#include "gimg/engine/plan.h"

#include <glm/vec2.hpp>

#include <map>
#include <memory>

namespace gimg::passes::detail {

struct BicgState {
    std::vector<glm::dvec2> x, r, r0, p, v;
    glm::dvec2 rho{1.0}, alpha{1.0}, omega{1.0};
    glm::dvec2 r0r{0.0}, rr{0.0};  // r0 . r and r . r now
};

// The Laplacian a multigrid preconditioner of a non-symmetric A is built from: off-diagonal entries
// (a_ij + a_ji) / 2, each diagonal the sum of its row's off-diagonal magnitudes plus `boundary`
// (row i's |a_ij| summed over the columns eliminated as fixed) plus A's own excess over diagonal
// dominance, max(0, |a_ii| - sum_j |a_ij|) (a shift or mass term; 0 on Tutte and Floater rows).
// Symmetric and diagonally dominant, so positive definite where a row touches the boundary or has
// an excess, as build_multigrid needs. A's own diagonal (1 on every row of a row-normalised system)
// would leave it indefinite wherever w_ij + w_ji > 2 w; the larger of the two doubled the iterations.
SpdSystem symmetric_laplacian(const CsrMatrix& a, const std::vector<double>& boundary);

// `a` holds every entry, diagonal included (no zero diagonal).
BicgState start_bicgstab(const CsrMatrix& a, const std::vector<glm::dvec2>& b, const std::vector<glm::dvec2>& x0);
// `mg`: the multigrid preconditioner's hierarchy (its finest level a's rows), or null for Jacobi.
void bicgstab_cpu(const CsrMatrix& a, BicgState& state, std::uint32_t iterations, const Multigrid* mg = nullptr);

class GpuBicgstab {
public:
    // Uploads a, the start and, with mg, its V-cycle, in one submission (Context::batch_uploads).
    GpuBicgstab(Context& ctx, const CsrMatrix& a, const BicgState& start, const Multigrid* mg = nullptr);
    // With a V-cycle already uploaded, which must outlive the solver.
    GpuBicgstab(Context& ctx, const CsrMatrix& a, const BicgState& start, GpuVcycle& cycle);
    // Runs `iterations` iterations; returns (r0 . r, r . r) per right-hand side after them.
    std::pair<glm::dvec2, glm::dvec2> run(std::uint32_t iterations);
    std::vector<glm::dvec2> solution();

private:
    Plan& plan_for(std::uint32_t iterations);
    Context& ctx_;
    std::uint32_t rows_ = 0;
    Image a_rows_, a_entries_;
    Image x_, r_, r0_, p_, v_, y_, s_, z_, t_;
    Buffer scalars_, sums_rr_;
    void upload(const CsrMatrix& a, const BicgState& start);
    std::unique_ptr<GpuVcycle> own_cycle_;
    GpuVcycle* cycle_ = nullptr;  // null: Jacobi
    std::map<std::uint32_t, std::unique_ptr<Plan>> plans_;
};

}  // namespace gimg::passes::detail

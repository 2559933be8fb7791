#pragma once
// Sparse linear systems A X = B on the GPU, for any capability: A square in compressed rows, some
// rows fixed to given values (Dirichlet rows), 1 to 4 right-hand sides (docs/solvers.md).
//
//  - solve_symmetric: A symmetric positive definite on the free rows (cotangent Laplacians with
//    positive weights, mass-weighted Laplacians): conjugate gradients preconditioned by one
//    smoothed-aggregation multigrid V-cycle (Vanek, Mandel and Brezina 1996), so the iterations
//    stay flat as the mesh grows. The spherical maps' chart solves run on the same code.
//  - solve_general: A non-symmetric (Floater's shape-preserving weights, reweighted Tutte
//    systems, row-normalised weights): BiCGSTAB (van der Vorst 1992), preconditioned by Jacobi or,
//    for Laplacian-like matrices, by a V-cycle of the same multigrid (SolveOptions::preconditioner).
//
// Each has a CPU twin that runs the same iterations in the same order of operations, which tests
// hold the GPU to. Bad input (a matrix that is not square, an index out of range, a right-hand side
// of the wrong length, a zero or non-finite diagonal on a free row, an asymmetric matrix given to
// solve_symmetric) throws geo::InputError naming it; a breakdown of the iteration throws
// geo::InputError saying which scalar vanished and what that means for the matrix.

#include "gimg/engine/context.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace gimg::passes {

// An n x n matrix in compressed rows (entries of a row in any order, at most one per column).
struct SparseMatrix {
    std::size_t size = 0;                   // n
    std::vector<std::uint32_t> offsets{0};  // n + 1
    std::vector<std::uint32_t> columns;
    std::vector<double> values;
};

struct LinearSystem {
    SparseMatrix a;
    std::uint32_t rhs_count = 1;       // 1 to 4 right-hand sides
    std::vector<double> b;             // n * rhs_count, b[i * rhs_count + c]
    std::vector<std::uint8_t> fixed;   // empty (none) or one per row: 1 = row i is x_i = fixed_values
    std::vector<double> fixed_values;  // empty (zeros) or n * rhs_count; read on fixed rows only
    std::vector<double> start;         // empty (zeros) or n * rhs_count: the first guess of free rows
};

// solve_general's preconditioner (solve_symmetric always uses the V-cycle).
//  - Jacobi: the diagonal; for any matrix with a nonzero diagonal. Its iterations grow with the
//    mesh's diameter in rings.
//  - Multigrid: one V-cycle of the smoothed-aggregation hierarchy of the Laplacian made from A's
//    symmetric part (off-diagonals (a_ij + a_ji) / 2, each diagonal the sum of its row's
//    off-diagonal magnitudes, fixed columns included, plus the row's excess over diagonal
//    dominance). For Laplacian-like A (Tutte, Floater and
//    their reweightings, diffusion-dominated operators), whose iterations it keeps flat as the mesh
//    grows: mannequin_devil's Floater map to 1e-8 in 17 iterations instead of 408. Costs a
//    hierarchy build (linear in the nonzeros) a solve and two cycles an iteration. Falls back to
//    Jacobi when the matrix has too few off-diagonal entries to coarsen.
enum class Preconditioner { Jacobi, Multigrid };

// What solve_general may keep from one call to the next (SolveOptions::reuse): the multigrid
// preconditioner's hierarchy, built by the first call and used again while the number of free rows
// stays the same. For a run of systems on one mesh whose values drift, such as the reweighting
// iterations of a square map: the first system's hierarchy still preconditions the later ones
// (mannequin_devil: within one or two iterations of a rebuilt one) and saves its build each time.
// A caller whose systems change more should build afresh (no cache, or clear()). solve_general
// on a GPU also keeps the hierarchy's upload, so a cache must be cleared or destroyed before the
// Context it was used with.
class PreconditionerCache {
public:
    PreconditionerCache();
    ~PreconditionerCache();
    PreconditionerCache(const PreconditionerCache&) = delete;
    PreconditionerCache& operator=(const PreconditionerCache&) = delete;
    void clear();
    struct Hierarchy;
    std::unique_ptr<Hierarchy> hierarchy;  // empty until a multigrid solve builds one
};

struct SolveOptions {
    // Stop when the relative residual is at most this: |r| / |b| in the preconditioner's norm for
    // solve_symmetric, in the Euclidean norm for solve_general (both on the free rows).
    double tolerance = 1e-8;
    std::size_t max_iterations = 10000;
    std::uint32_t iterations_per_check = 16;                 // iterations recorded per submission (GPU)
    Preconditioner preconditioner = Preconditioner::Jacobi;  // solve_general's
    PreconditionerCache* reuse = nullptr;                    // solve_general's, with Multigrid
};

struct SolveResult {
    std::vector<double> x;  // n * rhs_count; fixed rows hold their values
    std::size_t iterations = 0;
    double residual = 0.0;   // the relative residual at the end
    bool converged = false;  // residual <= tolerance
};

SolveResult solve_symmetric(Context& ctx, const LinearSystem& system, const SolveOptions& options = {});
SolveResult solve_symmetric_cpu(const LinearSystem& system, const SolveOptions& options = {});

SolveResult solve_general(Context& ctx, const LinearSystem& system, const SolveOptions& options = {});
SolveResult solve_general_cpu(const LinearSystem& system, const SolveOptions& options = {});

// For a run of systems whose matrices drift (reweighting iterations): sets system.start to the
// last of `past` (earlier solutions, oldest first, each n * rhs_count) plus the combination of its
// differences from the others that leaves the least residual |b - A x| on the free rows, per
// right-hand side. Costs one product with A per difference; with one past solution the start is
// that solution.
void project_start(LinearSystem& system, const std::vector<std::vector<double>>& past);

}  // namespace gimg::passes

#pragma once
// Sparse linear systems A X = B on the GPU, for any capability: A square in compressed rows, some
// rows fixed to given values (Dirichlet rows), 1 to 4 right-hand sides (docs/solvers.md).
//
//  - solve_symmetric: A symmetric positive definite on the free rows (cotangent Laplacians with
//    positive weights, mass-weighted Laplacians): conjugate gradients preconditioned by one
//    smoothed-aggregation multigrid V-cycle (Vanek, Mandel and Brezina 1996), so the iterations
//    stay flat as the mesh grows. The spherical maps' chart solves run on the same code.
//  - solve_general: A non-symmetric (Floater's shape-preserving weights, reweighted Tutte
//    systems, row-normalised weights): BiCGSTAB (van der Vorst 1992) with a Jacobi preconditioner.
//
// Each has a CPU twin that runs the same iterations in the same order of operations, which tests
// hold the GPU to. Bad input (a matrix that is not square, an index out of range, a right-hand side
// of the wrong length, a zero or non-finite diagonal on a free row, an asymmetric matrix given to
// solve_symmetric) throws geo::InputError naming it; a breakdown of the iteration throws
// geo::InputError saying which scalar vanished and what that means for the matrix.

#include "gimg/engine/context.h"

#include <cstddef>
#include <cstdint>
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

struct SolveOptions {
    // Stop when the relative residual is at most this: |r| / |b| in the preconditioner's norm for
    // solve_symmetric, in the Euclidean norm for solve_general (both on the free rows).
    double tolerance = 1e-8;
    std::size_t max_iterations = 10000;
    std::uint32_t iterations_per_check = 16;  // iterations recorded per submission (GPU)
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

}  // namespace gimg::passes

// Sparse Cholesky (LDL^T) solve of a Dirichlet problem, with the pinned columns moved to the
// right-hand side so the reduced matrix stays symmetric.
#include "sphere/linear/dirichlet_solve.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <cmath>

namespace gimg::passes::linear_sphere {

DirichletSolution solve_dirichlet(std::size_t vertex_count, const std::vector<StiffnessEntry>& stiffness,
                                  const std::vector<std::uint8_t>& pinned,
                                  const std::vector<std::complex<double>>& pinned_values) {
    DirichletSolution out;
    out.z.assign(vertex_count, {0.0, 0.0});

    // Free vertices are renumbered 0..free_count-1.
    std::vector<std::int64_t> free_index(vertex_count, -1);
    Eigen::Index free_count = 0;
    for (std::size_t v = 0; v < vertex_count; ++v) {
        if (pinned[v])
            out.z[v] = pinned_values[v];
        else
            free_index[v] = free_count++;
    }
    if (free_count == 0) {
        out.ok = true;
        return out;
    }

    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(stiffness.size());
    Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(free_count, 2);
    for (const StiffnessEntry& e : stiffness) {
        const std::int64_t r = free_index[e.row];
        if (r < 0) continue;  // a pinned row: its equation is replaced by the prescribed value
        const std::int64_t c = free_index[e.col];
        if (c >= 0) {
            triplets.emplace_back(Eigen::Index(r), Eigen::Index(c), e.value);
        } else {
            rhs(r, 0) -= e.value * pinned_values[e.col].real();
            rhs(r, 1) -= e.value * pinned_values[e.col].imag();
        }
    }
    Eigen::SparseMatrix<double> k(free_count, free_count);
    k.setFromTriplets(triplets.begin(), triplets.end());

    // LDL^T rather than LL^T: the matrix is positive definite in exact arithmetic, but badly shaped
    // meshes can push tiny pivots below zero, and LDL^T still gets through those.
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    solver.compute(k);
    if (solver.info() != Eigen::Success) {
        out.why = "sparse factorisation failed (" + std::to_string(free_count) + " unknowns)";
        return out;
    }
    const Eigen::MatrixX2d x = solver.solve(rhs);
    if (solver.info() != Eigen::Success) {
        out.why = "sparse back-substitution failed";
        return out;
    }
    for (std::size_t v = 0; v < vertex_count; ++v) {
        if (free_index[v] < 0) continue;
        const double re = x(free_index[v], 0), im = x(free_index[v], 1);
        if (!std::isfinite(re) || !std::isfinite(im)) {
            out.why = "the solve produced NaN or infinite coordinates";
            return out;
        }
        out.z[v] = {re, im};
    }
    out.ok = true;
    return out;
}

}  // namespace gimg::passes::linear_sphere

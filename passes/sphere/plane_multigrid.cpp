// Smoothed-aggregation multigrid for the planar polish: the setup on the CPU and the CPU twin of
// the V-cycle.
#include "plane_multigrid.h"

#include "gimg/engine/error.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace gimg::passes::detail {

namespace {

using Sparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// Above this the dense coarsest level would cost more than the cycle it ends.
constexpr std::size_t kMaxDenseRows = 1024;
// A level that keeps more than this share of its rows is not worth another level.
constexpr double kStalledCoarsening = 0.9;
// Power iterations for the largest eigenvalue of D^-1 A; the damping 4 / (3 rho) leaves a
// margin of 1.5 against an underestimate before Jacobi amplifies anything.
constexpr int kPowerIterations = 20;

Sparse sparse_of_problem(const PlaneProblem& problem) {
    const auto m = Eigen::Index(problem.rows());
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(problem.columns.size() + problem.rows());
    for (Eigen::Index i = 0; i < m; ++i) {
        entries.emplace_back(i, i, problem.diagonal[std::size_t(i)]);
        for (std::uint32_t k = problem.row_offsets[std::size_t(i)]; k < problem.row_offsets[std::size_t(i) + 1]; ++k)
            entries.emplace_back(i, Eigen::Index(problem.columns[k]), problem.values[k]);
    }
    Sparse a(m, m);
    a.setFromTriplets(entries.begin(), entries.end());
    return a;
}

CsrMatrix csr_of(const Sparse& s) {
    CsrMatrix m;
    m.cols = std::size_t(s.cols());
    m.offsets.clear();
    m.offsets.reserve(std::size_t(s.rows()) + 1);
    m.offsets.push_back(0);
    for (Eigen::Index i = 0; i < s.rows(); ++i) {
        for (Sparse::InnerIterator it(s, i); it; ++it) {
            m.columns.push_back(std::uint32_t(it.col()));
            m.values.push_back(it.value());
        }
        m.offsets.push_back(std::uint32_t(m.columns.size()));
    }
    return m;
}

// The largest eigenvalue of D^-1 A (similar to the symmetric D^-1/2 A D^-1/2) by power iteration
// from a fixed start, so a run is reproducible.
double largest_jacobi_eigenvalue(const Sparse& a, const Eigen::VectorXd& diagonal) {
    Eigen::VectorXd v(a.rows());
    for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = 1.0 + 0.5 * std::sin(double(i));
    double lambda = 0.0;
    for (int k = 0; k < kPowerIterations; ++k) {
        const double norm = v.norm();
        if (!(norm > 0.0)) break;
        v /= norm;
        Eigen::VectorXd w = (a * v).cwiseQuotient(diagonal);
        lambda = v.dot(w);
        v = std::move(w);
    }
    return std::max(lambda, v.norm());
}

// Aggregates of strongly connected rows (Vanek et al.'s three passes, every off-diagonal entry
// strong): each row's aggregate number in `of`; returns how many.
Eigen::Index aggregate(const Sparse& a, std::vector<int>& of) {
    const Eigen::Index n = a.rows();
    of.assign(std::size_t(n), -1);
    int count = 0;
    // 1: a row all of whose neighbours are free seeds an aggregate with them.
    for (Eigen::Index i = 0; i < n; ++i) {
        if (of[std::size_t(i)] >= 0) continue;
        bool free = true;
        for (Sparse::InnerIterator it(a, i); it && free; ++it) free = it.col() == i || of[std::size_t(it.col())] < 0;
        if (!free) continue;
        for (Sparse::InnerIterator it(a, i); it; ++it) of[std::size_t(it.col())] = count;
        of[std::size_t(i)] = count++;
    }
    // 2: the others join a neighbouring aggregate from pass 1.
    std::vector<int> joined = of;
    for (Eigen::Index i = 0; i < n; ++i) {
        if (of[std::size_t(i)] >= 0) continue;
        for (Sparse::InnerIterator it(a, i); it; ++it)
            if (of[std::size_t(it.col())] >= 0) {
                joined[std::size_t(i)] = of[std::size_t(it.col())];
                break;
            }
    }
    of = std::move(joined);
    // 3: what is left (rows without neighbours) stands alone.
    for (Eigen::Index i = 0; i < n; ++i)
        if (of[std::size_t(i)] < 0) of[std::size_t(i)] = count++;
    return count;
}

std::vector<double> dense_inverse(const Sparse& a) {
    const Eigen::MatrixXd dense = Eigen::MatrixXd(a);
    const Eigen::Index n = dense.rows();
    Eigen::MatrixXd inverse = Eigen::MatrixXd::Identity(n, n);
    if (n > 0) inverse = dense.ldlt().solve(inverse);
    std::vector<double> out(std::size_t(n * n));
    for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j) out[std::size_t(i * n + j)] = inverse(i, j);
    return out;
}

// x = S b, r = b - A x: the first Jacobi step from zero and its residual, A x summed as
// (a_ij s_j) b_j, as mg_presmooth does with its pre-multiplied entries.
void presmooth(const MultigridLevel& level, const std::vector<glm::dvec2>& b, std::vector<glm::dvec2>& x,
               std::vector<glm::dvec2>& r) {
    const std::size_t n = b.size();
    const CsrMatrix& a = level.a;
    x.resize(n);
    r.resize(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = level.smoother[i] * b[i];
    for (std::size_t i = 0; i < n; ++i) {
        glm::dvec2 sum(0.0);
        for (std::uint32_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k)
            sum += (a.values[k] * level.smoother[a.columns[k]]) * b[a.columns[k]];
        r[i] = b[i] - sum;
    }
}

std::vector<glm::dvec2> cycle(const PlaneMultigrid& mg, std::size_t l, const std::vector<glm::dvec2>& b) {
    if (l == mg.levels.size()) {
        const std::size_t n = mg.coarsest_rows();
        std::vector<glm::dvec2> x(n, glm::dvec2(0.0));
        for (std::size_t i = 0; i < n; ++i) {
            glm::dvec2 sum(0.0);
            for (std::size_t j = 0; j < n; ++j) sum += mg.coarsest_inverse[i * n + j] * b[j];
            x[i] = sum;
        }
        return x;
    }
    const MultigridLevel& level = mg.levels[l];
    std::vector<glm::dvec2> x, r;
    presmooth(level, b, x, r);
    std::vector<glm::dvec2> coarse_b(level.restrict_.rows());
    for (std::size_t i = 0; i < coarse_b.size(); ++i) coarse_b[i] = row_times(level.restrict_, r, i);
    const std::vector<glm::dvec2> coarse_x = cycle(mg, l + 1, coarse_b);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += row_times(level.prolong, coarse_x, i);
    std::vector<glm::dvec2> z(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) z[i] = x[i] + level.smoother[i] * (b[i] - row_times(level.a, x, i));
    return z;
}

}  // namespace

glm::dvec2 row_times(const CsrMatrix& m, const std::vector<glm::dvec2>& v, std::size_t i) {
    glm::dvec2 sum(0.0);
    for (std::uint32_t k = m.offsets[i]; k < m.offsets[i + 1]; ++k) sum += m.values[k] * v[m.columns[k]];
    return sum;
}

PlaneMultigrid build_plane_multigrid(const PlaneProblem& problem) {
    PlaneMultigrid mg;
    Sparse a = sparse_of_problem(problem);
    while (std::size_t(a.rows()) > kMultigridDenseRows) {
        const Eigen::VectorXd diagonal = a.diagonal();
        std::vector<int> of;
        const Eigen::Index coarse = aggregate(a, of);
        if (double(coarse) > kStalledCoarsening * double(a.rows())) break;

        const double omega = 4.0 / (3.0 * largest_jacobi_eigenvalue(a, diagonal));
        std::vector<Eigen::Triplet<double>> entries;
        for (Eigen::Index i = 0; i < a.rows(); ++i) entries.emplace_back(i, of[std::size_t(i)], 1.0);
        Sparse tentative(a.rows(), coarse);
        tentative.setFromTriplets(entries.begin(), entries.end());
        const Eigen::VectorXd scale = omega * diagonal.cwiseInverse();
        Sparse prolong = tentative - Sparse(scale.asDiagonal() * Sparse(a * tentative));
        prolong.prune(0.0);
        const Sparse restriction = prolong.transpose();
        Sparse next = restriction * Sparse(a * prolong);
        next.prune(0.0);

        MultigridLevel level;
        level.a = csr_of(a);
        level.smoother.assign(scale.data(), scale.data() + scale.size());
        level.prolong = csr_of(prolong);
        level.restrict_ = csr_of(restriction);
        mg.levels.push_back(std::move(level));
        a = std::move(next);
    }
    if (std::size_t(a.rows()) > kMaxDenseRows)
        throw Error(ErrorKind::InvalidArgument, "plane multigrid: aggregation stalled at " + std::to_string(a.rows()) + " rows");
    mg.coarsest = csr_of(a);
    mg.coarsest_inverse = dense_inverse(a);
    return mg;
}

std::vector<glm::dvec2> apply_multigrid_cpu(const PlaneMultigrid& mg, const std::vector<glm::dvec2>& b) {
    return cycle(mg, 0, b);
}

}  // namespace gimg::passes::detail

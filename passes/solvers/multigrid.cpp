// Smoothed-aggregation multigrid for the planar polish: the setup on the CPU and the CPU twin of
// the V-cycle.
#include "solvers/multigrid.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

namespace gimg::passes::detail {

namespace {

using Sparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// Above this the dense coarsest level would cost more than the cycle it ends.
constexpr std::size_t kMaxDenseRows = 1024;
// A level that keeps more than this share of its rows is not worth another level.
constexpr double kStalledCoarsening = 0.9;
// Power iterations for the largest eigenvalue of D^-1 A; the prolongator's damping 4 / (3 rho)
// leaves a margin of 1.5 against an underestimate before Jacobi amplifies anything, the
// smoother's interval one of 1.3 (ChebyshevSmoother).
constexpr int kPowerIterations = 20;
// Strong connections for the aggregation: |a_ij| >= this sqrt(a_ii a_jj), Vanek, Mandel and
// Brezina's 0.08, on every level. Against taking every entry as strong (as this solver did
// first), the conjugate gradients' iterations (start + polish) fell from 10 + 13 to 7 + 9 on
// armadillo_loop1, 17 + 28 to 7 + 11 on cow, 22 + 64 to 10 + 31 on triceratops, 10 + 14 to 6 + 8
// on bunny_loop1 (the start's first check after 6 iterations, pinned_start.cpp), for a setup a
// few milliseconds longer. (Their 0.08 halved on every coarser level gave the same counts to +-1.)
constexpr double kStrongConnection = 0.08;
// The smoother's interval, in multiples of rho: its lower end 0.1 needed 1-2 fewer iterations
// than 0.3 on armadillo and armadillo_loop1 (0.05 no fewer), its upper end the same from 1.1 to
// 1.3.
constexpr double kChebyshevLow = 0.1;
constexpr double kChebyshevHigh = 1.2;

// A sparse row as (column, value) pairs in any order.
using Row = std::vector<std::pair<Eigen::Index, double>>;

// Sorts a row by column, keeping the given order among equal columns: by insertion, since rows
// hold a handful of entries (std::stable_sort asked the heap for a buffer for every row:
// sparse_of_problem and smoothed_prolongator took 16 ms of armadillo_loop1's 55 ms setup with it,
// 11.5 ms without).
void sort_row(Row& row) {
    for (std::size_t k = 1; k < row.size(); ++k) {
        const auto entry = row[k];
        std::size_t j = k;
        for (; j > 0 && row[j - 1].first > entry.first; --j) row[j] = row[j - 1];
        row[j] = entry;
    }
}

// Sorts `row` and appends it to `columns` and `values`: sorted by column, a repeated column summed
// (in the order given), exact zeros left out when `drop_zeros`.
void append_row(Row& row, bool drop_zeros, std::vector<int>& columns, std::vector<double>& values) {
    sort_row(row);
    for (std::size_t k = 0; k < row.size();) {
        double value = 0.0;
        std::size_t next = k;
        for (; next < row.size() && row[next].first == row[k].first; ++next) value += row[next].second;
        if (!drop_zeros || value != 0.0) {
            columns.push_back(int(row[k].first));
            values.push_back(value);
        }
        k = next;
    }
}

// The compressed row-major matrix whose row i `fill_row(i, row)` lists (column, value) in any
// order (append_row merges it), built in two halves of the rows on two threads and joined: each
// row comes out as one thread would build it, so the matrix is the same.
template <class FillRow>
Sparse rows_in_halves(Eigen::Index rows, Eigen::Index cols, bool drop_zeros, const FillRow& fill_row) {
    struct Part {
        std::vector<int> ends, columns;  // ends: the end of each row in columns / values
        std::vector<double> values;
    };
    Part parts[2];
    const std::size_t half = std::max<std::size_t>((std::size_t(rows) + 1) / 2, 1);
    geo::parallel_for_chunks(std::size_t(rows), half, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
        Part& part = parts[chunk];
        part.ends.reserve(end - begin);
        Row row;
        for (std::size_t i = begin; i < end; ++i) {
            row.clear();
            fill_row(Eigen::Index(i), row);
            append_row(row, drop_zeros, part.columns, part.values);
            part.ends.push_back(int(part.columns.size()));
        }
    });
    Sparse out(rows, cols);
    out.resizeNonZeros(Eigen::Index(parts[0].columns.size() + parts[1].columns.size()));
    int* outer = out.outerIndexPtr();
    outer[0] = 0;
    Eigen::Index i = 0;
    int offset = 0;
    for (const Part& part : parts) {
        for (int end : part.ends) outer[++i] = offset + end;
        std::copy(part.columns.begin(), part.columns.end(), out.innerIndexPtr() + offset);
        std::copy(part.values.begin(), part.values.end(), out.valuePtr() + offset);
        offset += int(part.columns.size());
    }
    return out;
}

// The problem's rows, already compressed, filled in directly (setFromTriplets sorted all of
// them again: 8-16 ms on armadillo_loop1).
Sparse sparse_of_problem(const SpdSystem& problem) {
    const auto m = Eigen::Index(problem.rows());
    // Explicit zeros kept, as setFromTriplets kept them.
    return rows_in_halves(m, m, false, [&](Eigen::Index i, Row& row) {
        row.emplace_back(i, problem.diagonal[std::size_t(i)]);
        for (std::uint32_t k = problem.row_offsets[std::size_t(i)]; k < problem.row_offsets[std::size_t(i) + 1]; ++k)
            row.emplace_back(Eigen::Index(problem.columns[k]), problem.values[k]);
    });
}

// P = (I - omega D^-1 A) T, T the tentative prolongator (row i: a 1 in the column of its
// aggregate `of[i]`), row by row: A T sums each row's entries by aggregate. Exact zeros are left
// out. (Built from Eigen products with T it took 14 ms of armadillo_loop1's setup; this, 3.)
Sparse smoothed_prolongator(const Sparse& a, const Eigen::VectorXd& diagonal, const std::vector<int>& of,
                            Eigen::Index coarse, double omega) {
    return rows_in_halves(a.rows(), coarse, true, [&](Eigen::Index i, Row& row) {
        const double scale = omega / diagonal[i];
        row.emplace_back(of[std::size_t(i)], 1.0);
        for (Sparse::InnerIterator it(a, i); it; ++it) row.emplace_back(of[std::size_t(it.col())], -scale * it.value());
    });
}

// lhs * rhs with the rows of lhs in two halves on two threads: each row of the product is
// computed as in one product, so the result is the same (the Galerkin products were 35-40 ms of
// armadillo_loop1's 66 ms setup on one thread).
Sparse product_in_halves(const Sparse& lhs, const Sparse& rhs) {
    const Eigen::Index rows = lhs.rows(), half = (rows + 1) / 2;
    Sparse parts[2];
    geo::parallel_for_chunks(std::size_t(rows), std::size_t(std::max<Eigen::Index>(half, 1)),
                             [&](std::size_t chunk, std::size_t begin, std::size_t end) {
                                 parts[chunk] = lhs.middleRows(Eigen::Index(begin), Eigen::Index(end - begin)) * rhs;
                             });
    Sparse out(rows, rhs.cols());
    out.reserve(parts[0].nonZeros() + parts[1].nonZeros());
    Eigen::Index i = 0;
    for (const Sparse& part : parts)
        for (Eigen::Index r = 0; r < part.rows(); ++r, ++i) {
            out.startVec(i);
            for (Sparse::InnerIterator it(part, r); it; ++it) out.insertBack(i, it.col()) = it.value();
        }
    out.finalize();
    return out;
}

CsrMatrix csr_of(const Sparse& s) {
    if (!s.isCompressed()) {
        Sparse compressed = s;
        compressed.makeCompressed();
        return csr_of(compressed);
    }
    CsrMatrix m;
    m.cols = std::size_t(s.cols());
    m.offsets.assign(s.outerIndexPtr(), s.outerIndexPtr() + s.rows() + 1);
    m.columns.assign(s.innerIndexPtr(), s.innerIndexPtr() + s.nonZeros());
    m.values.assign(s.valuePtr(), s.valuePtr() + s.nonZeros());
    return m;
}

// The largest eigenvalue of D^-1 A (similar to the symmetric D^-1/2 A D^-1/2) by power iteration
// from a fixed start, so a run is reproducible.
double largest_jacobi_eigenvalue(const Sparse& a, const Eigen::VectorXd& diagonal) {
    Eigen::VectorXd v(a.rows()), w(a.rows());
    for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = 1.0 + 0.5 * std::sin(double(i));
    // The products in two halves of the rows on two threads (the same sums as one product).
    const std::size_t half = std::max<std::size_t>((std::size_t(a.rows()) + 1) / 2, 1);
    double lambda = 0.0;
    for (int k = 0; k < kPowerIterations; ++k) {
        const double norm = v.norm();
        if (!(norm > 0.0)) break;
        v /= norm;
        geo::parallel_for_chunks(std::size_t(a.rows()), half, [&](std::size_t, std::size_t begin, std::size_t end) {
            // Row by row without a temporary, summed in storage order as Eigen's product sums.
            const int* outer = a.outerIndexPtr();
            const int* inner = a.innerIndexPtr();
            const double* values = a.valuePtr();
            for (std::size_t i = begin; i < end; ++i) {
                double sum = 0.0;
                for (int e = outer[i]; e < outer[i + 1]; ++e) sum += values[e] * v[inner[e]];
                w[Eigen::Index(i)] = sum / diagonal[Eigen::Index(i)];
            }
        });
        lambda = v.dot(w);
        std::swap(v, w);
    }
    return std::max(lambda, v.norm());
}

// Aggregates of strongly connected rows (Vanek et al.'s three passes): each row's aggregate number
// in `of`; returns how many. Row j is a strong neighbour of row i when
// |a_ij| >= kStrongConnection sqrt(a_ii a_jj).
Eigen::Index aggregate(const Sparse& a, const Eigen::VectorXd& diagonal, std::vector<int>& of) {
    const Eigen::Index n = a.rows();
    auto strong = [&](Eigen::Index i, const Sparse::InnerIterator& it) {
        return it.col() != i &&
               std::abs(it.value()) >= kStrongConnection * std::sqrt(std::abs(diagonal[i] * diagonal[it.col()]));
    };
    of.assign(std::size_t(n), -1);
    int count = 0;
    // 1: a row all of whose strong neighbours are free seeds an aggregate with them.
    for (Eigen::Index i = 0; i < n; ++i) {
        if (of[std::size_t(i)] >= 0) continue;
        bool free = true;
        for (Sparse::InnerIterator it(a, i); it && free; ++it) free = !strong(i, it) || of[std::size_t(it.col())] < 0;
        if (!free) continue;
        for (Sparse::InnerIterator it(a, i); it; ++it)
            if (strong(i, it)) of[std::size_t(it.col())] = count;
        of[std::size_t(i)] = count++;
    }
    // 2: the others join the aggregate of a strong neighbour from pass 1.
    std::vector<int> joined = of;
    for (Eigen::Index i = 0; i < n; ++i) {
        if (of[std::size_t(i)] >= 0) continue;
        for (Sparse::InnerIterator it(a, i); it; ++it)
            if (strong(i, it) && of[std::size_t(it.col())] >= 0) {
                joined[std::size_t(i)] = of[std::size_t(it.col())];
                break;
            }
    }
    of = std::move(joined);
    // 3: what is left (rows without strong neighbours) stands alone.
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

template <class T>
using Vec2 = glm::vec<2, T>;
template <class T>
using Vectors = std::vector<Vec2<T>>;

// Row i of m v in T with m's entries `values` (in T), summed in the shaders' order.
template <class T>
Vec2<T> row_times_in(const CsrMatrix& m, const T* values, const Vectors<T>& v, std::size_t i) {
    Vec2<T> sum(T(0));
    for (std::uint32_t k = m.offsets[i]; k < m.offsets[i + 1]; ++k) sum += values[k] * v[m.columns[k]];
    return sum;
}

// A level's entries in T: A's, A's over their column's diagonal, P's, R's.
template <class T>
struct LevelValues {
    const T *a, *a_over_diagonal, *prolong, *restrict_;
};
template <class T>
LevelValues<T> values_in(const MultigridLevel& l) {
    if constexpr (std::is_same_v<T, float>)
        return {l.a32.data(), l.a_over_diagonal32.data(), l.prolong32.data(), l.restrict32.data()};
    else
        return {l.a.values.data(), l.a_over_diagonal.data(), l.prolong.values.data(), l.restrict_.values.data()};
}

std::vector<float> rounded(const std::vector<double>& v) { return std::vector<float>(v.begin(), v.end()); }

// The smoother from zero and its residual (the header's "down" line): x = D^-1 (c0 b + c1 r1) and
// r = b - A x. A's entries come divided by their column's diagonal, as mg_presmooth_first and
// mg_presmooth_second read them.
template <class T>
void presmooth(const MultigridLevel& level, const Vectors<T>& b, Vectors<T>& x, Vectors<T>& r) {
    const std::size_t n = b.size();
    const ChebyshevSmoother& s = level.smoother;
    const T c0 = T(s.c0), c1 = T(s.c1), theta_inverse = T(s.theta_inverse);
    const T* ad = values_in<T>(level).a_over_diagonal;
    Vectors<T> mix(n);  // c0 b + c1 r1
    for (std::size_t i = 0; i < n; ++i)
        mix[i] = c0 * b[i] + c1 * (b[i] - theta_inverse * row_times_in(level.a, ad, b, i));
    x.resize(n);
    r.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = T(level.inverse_diagonal[i]) * mix[i];
        r[i] = b[i] - row_times_in(level.a, ad, mix, i);
    }
}

// The smoother from x (the header's "up" line).
template <class T>
Vectors<T> postsmooth(const MultigridLevel& level, const Vectors<T>& b, const Vectors<T>& x) {
    const std::size_t n = b.size();
    const ChebyshevSmoother& s = level.smoother;
    const T c1 = T(s.c1), k = T(s.k), theta_inverse = T(s.theta_inverse);
    const T* a = values_in<T>(level).a;
    Vectors<T> x1(n), z(n);
    for (std::size_t i = 0; i < n; ++i)
        x1[i] = x[i] + (theta_inverse * T(level.inverse_diagonal[i])) * (b[i] - row_times_in(level.a, a, x, i));
    for (std::size_t i = 0; i < n; ++i)
        z[i] =
            x1[i] + k * (x1[i] - x[i]) + (c1 * T(level.inverse_diagonal[i])) * (b[i] - row_times_in(level.a, a, x1, i));
    return z;
}

template <class T>
Vectors<T> cycle(const Multigrid& mg, std::size_t l, const Vectors<T>& b) {
    if (l == mg.levels.size()) {
        // The dense level sums in double whatever the cycle's type (mg_coarsest).
        const std::size_t n = mg.coarsest_rows();
        Vectors<T> x(n, Vec2<T>(T(0)));
        for (std::size_t i = 0; i < n; ++i) {
            glm::dvec2 sum(0.0);
            for (std::size_t j = 0; j < n; ++j) sum += mg.coarsest_inverse[i * n + j] * glm::dvec2(b[j]);
            x[i] = Vec2<T>(sum);
        }
        return x;
    }
    const MultigridLevel& level = mg.levels[l];
    Vectors<T> x, r;
    presmooth(level, b, x, r);
    Vectors<T> coarse_b(level.restrict_.rows());
    const LevelValues<T> values = values_in<T>(level);
    for (std::size_t i = 0; i < coarse_b.size(); ++i)
        coarse_b[i] = row_times_in(level.restrict_, values.restrict_, r, i);
    const Vectors<T> coarse_x = cycle(mg, l + 1, coarse_b);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += row_times_in(level.prolong, values.prolong, coarse_x, i);
    return postsmooth(level, b, x);
}

template <class T>
std::vector<glm::dvec2> cycle_in(const Multigrid& mg, const std::vector<glm::dvec2>& b) {
    const Vectors<T> z = cycle(mg, 0, Vectors<T>(b.begin(), b.end()));
    return std::vector<glm::dvec2>(z.begin(), z.end());
}

}  // namespace

ChebyshevSmoother chebyshev_smoother(double rho) {
    const double low = kChebyshevLow * rho, high = kChebyshevHigh * rho;
    const double theta = 0.5 * (high + low), delta = 0.5 * (high - low), sigma = theta / delta;
    const double rho0 = 1.0 / sigma, rho1 = 1.0 / (2.0 * sigma - rho0);
    ChebyshevSmoother s;
    s.theta_inverse = 1.0 / theta;
    s.k = rho1 * rho0;
    s.c0 = (1.0 + s.k) / theta;
    s.c1 = 2.0 * rho1 / delta;
    return s;
}

glm::dvec2 row_times(const CsrMatrix& m, const std::vector<glm::dvec2>& v, std::size_t i) {
    return row_times_in(m, m.values.data(), v, i);
}

Multigrid build_multigrid(const SpdSystem& problem) {
    Multigrid mg;
    Sparse a = sparse_of_problem(problem);
    while (std::size_t(a.rows()) > kMultigridDenseRows) {
        const Eigen::VectorXd diagonal = a.diagonal();
        std::vector<int> of;
        Eigen::Index coarse = aggregate(a, diagonal, of);
        if (double(coarse) > kStalledCoarsening * double(a.rows())) {
            if (std::size_t(a.rows()) <= kMaxDenseRows) break;
            // Many rows without strong neighbours (pieces of one or two free vertices) leave the
            // aggregates as they were; pairing them by index still halves the level. A coarse
            // correction across uncoupled rows is weak, but the smoother solves such rows alone.
            for (int& o : of) o /= 2;
            coarse = (coarse + 1) / 2;
        }

        const double rho = largest_jacobi_eigenvalue(a, diagonal);
        const double omega = 4.0 / (3.0 * rho);
        const Sparse prolong = smoothed_prolongator(a, diagonal, of, coarse, omega);
        const Sparse restriction = prolong.transpose();
        Sparse next = product_in_halves(restriction, product_in_halves(a, prolong));
        next.prune(0.0);

        MultigridLevel level;
        level.a = csr_of(a);
        level.inverse_diagonal.resize(std::size_t(a.rows()));
        for (Eigen::Index i = 0; i < a.rows(); ++i) level.inverse_diagonal[std::size_t(i)] = 1.0 / diagonal[i];
        level.smoother = chebyshev_smoother(rho);
        level.prolong = csr_of(prolong);
        level.restrict_ = csr_of(restriction);
        level.a_over_diagonal.resize(level.a.values.size());
        for (std::size_t k = 0; k < level.a.values.size(); ++k)
            level.a_over_diagonal[k] = level.a.values[k] * level.inverse_diagonal[level.a.columns[k]];
        level.a32 = rounded(level.a.values);
        level.a_over_diagonal32 = rounded(level.a_over_diagonal);
        level.prolong32 = rounded(level.prolong.values);
        level.restrict32 = rounded(level.restrict_.values);
        mg.levels.push_back(std::move(level));
        a = std::move(next);
    }
    if (std::size_t(a.rows()) > kMaxDenseRows)
        throw geo::InputError("multigrid: aggregation stalled at " + std::to_string(a.rows()) + " rows");
    mg.coarsest = csr_of(a);
    mg.coarsest_inverse = dense_inverse(a);
    return mg;
}

std::vector<glm::dvec2> apply_multigrid_cpu(const Multigrid& mg, const std::vector<glm::dvec2>& b,
                                            CyclePrecision precision) {
    return precision == CyclePrecision::float32 ? cycle_in<float>(mg, b) : cycle_in<double>(mg, b);
}

}  // namespace gimg::passes::detail

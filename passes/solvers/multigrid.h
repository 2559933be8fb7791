#pragma once
// The preconditioner of the planar polish's conjugate gradients: one symmetric V-cycle of
// smoothed-aggregation algebraic multigrid (Vanek, Mandel and Brezina 1996). Jacobi alone needs
// about as many iterations as the mesh has rings across (bunny 900, armadillo_loop1 1,900): the
// error the relaxation leaves is smooth, which a diagonal cannot see. A V-cycle removes it on
// coarse grids, so the iterations no longer grow with the mesh.
//
// The hierarchy is built once on the CPU (aggregation, Galerkin products: linear in the
// nonzeros); the V-cycle runs on the render graph (conjugate_gradients.cpp) in float32, and apply_multigrid_cpu
// is its CPU twin in the same order of operations. On every level (D: A's diagonal):
//   down:  r1 = b - A (D^-1 b / theta),  x = D^-1 (c0 b + c1 r1),  r = b - A x,  bc = R r
//   below: xc = V(bc) (a dense inverse on the coarsest), x += P xc
//   up:    d = D^-1 (b - A x) / theta,  x1 = x + d,  r1 = b - A x1,  z = x1 + k d + c1 D^-1 r1
// Both smoothers are the same degree-2 Chebyshev polynomial in D^-1 A (ChebyshevSmoother), the
// first applied from zero: the cycle is symmetric, as conjugate gradients need. Damped Jacobi
// (one step each way, as this cycle had first) needed 22-31 iterations to 1e-8 on armadillo,
// armadillo_loop1 and dino, two Jacobi steps each way 16-22, degree 2 Chebyshev 13-18 for the
// same number of matrix products (measured on the CPU twin).
#include "solvers/spd_system.h"

#include <glm/vec2.hpp>

#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

// A sparse matrix in compressed rows, diagonal included where there is one.
struct CsrMatrix {
    std::size_t cols = 0;
    std::vector<std::uint32_t> offsets{0};  // rows + 1
    std::vector<std::uint32_t> columns;
    std::vector<double> values;
    std::size_t rows() const { return offsets.size() - 1; }
};

// Row i of m v, summed in the shaders' order.
glm::dvec2 row_times(const CsrMatrix& m, const std::vector<glm::dvec2>& v, std::size_t i);

// The degree-2 Chebyshev smoother of a level whose D^-1 A has the largest eigenvalue `rho`
// (estimated), damping the eigenvalues in [rho / 10, 1.2 rho]: with the residual polynomial
// T2((theta - lambda) / delta) / T2(theta / delta), theta and delta the interval's centre and
// half width, one application from x is
//   d = D^-1 (b - A x) / theta,  x1 = x + d,  x2 = x1 + k d + c1 D^-1 (b - A x1)
// and from zero x2 = D^-1 (c0 b + c1 (b - A x1)). It reduces every error component with an
// eigenvalue up to 1.3 rho (the interval's ends summed), a margin against an underestimated rho.
struct ChebyshevSmoother {
    double theta_inverse = 0.0;  // 1 / theta
    double c0 = 0.0;             // (1 + k) / theta
    double c1 = 0.0;             // 2 rho1 / delta
    double k = 0.0;              // rho1 rho0 (the Chebyshev recurrence's rho_k, not the eigenvalue)
};
ChebyshevSmoother chebyshev_smoother(double rho);

struct MultigridLevel {
    CsrMatrix a;                           // the level's operator: A on the finest, Galerkin products below
    std::vector<double> inverse_diagonal;  // 1 / a_ii
    ChebyshevSmoother smoother;
    CsrMatrix prolong;    // this level's rows, the next level's columns
    CsrMatrix restrict_;  // prolong transposed
    // The CPU cycle's entries: a's over their column's diagonal (the presmoothing's), and a's, P's,
    // R's and those rounded to float once, as the GPU's images hold them.
    std::vector<double> a_over_diagonal;
    std::vector<float> a32, a_over_diagonal32, prolong32, restrict32;
};

struct Multigrid {
    std::vector<MultigridLevel> levels;    // the smoothed levels, finest first (none for tiny problems)
    CsrMatrix coarsest;                    // the operator of the dense level
    std::vector<double> coarsest_inverse;  // row-major, coarsest.rows() squared
    std::size_t coarsest_rows() const { return coarsest.rows(); }
    const CsrMatrix& finest() const { return levels.empty() ? coarsest : levels.front().a; }
    std::size_t rows() const { return finest().rows(); }
};

// Levels are coarsened until at most this many rows are left, which are solved densely.
inline constexpr std::size_t kMultigridDenseRows = 256;

// Throws geo::InputError when aggregation stalls above 1024 rows (a matrix almost
// without off-diagonal entries), which the cotangent Laplacian of a connected mesh cannot be; the
// chart solve is then rejected, with the message in the map's note.
Multigrid build_multigrid(const SpdSystem& problem);

// The number type of a V-cycle. The GPU's cycle is float32 (conjugate_gradients.h says why): b rounded to
// float, every entry and constant rounded to float once (a_ij / a_jj before the rounding), sums in
// float in the shaders' order, but the dense level in double. float64 is the same cycle in double,
// the exact algorithm (symmetric to rounding), for tests.
enum class CyclePrecision { float32, float64 };

// z = V-cycle(b), in `precision`; with float32 the GPU cycle's CPU twin.
std::vector<glm::dvec2> apply_multigrid_cpu(const Multigrid& mg, const std::vector<glm::dvec2>& b,
                                            CyclePrecision precision = CyclePrecision::float32);

}  // namespace gimg::passes::detail

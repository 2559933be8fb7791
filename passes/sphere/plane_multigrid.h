#pragma once
// The preconditioner of the planar polish's conjugate gradients: one symmetric V-cycle of
// smoothed-aggregation algebraic multigrid (Vanek, Mandel and Brezina 1996). Jacobi alone needs
// about as many iterations as the mesh has rings across (bunny 900, armadillo_loop1 1,900): the
// error the relaxation leaves is smooth, which a diagonal cannot see. A V-cycle removes it on
// coarse grids, so the iterations no longer grow with the mesh.
//
// The hierarchy is built once on the CPU (aggregation, Galerkin products: linear in the
// nonzeros); the V-cycle runs on the render graph (plane_cg.cpp), and apply_multigrid_cpu is its
// CPU twin in the same order of operations:
//   x = S b, r = b - A x, bc = R r, xc = V(bc), x += P xc, z = x + S (b - A x)
// on every level (S: damped Jacobi, omega / diag(A)), with a dense inverse on the coarsest.
// One Jacobi step before and one after make the cycle symmetric, as conjugate gradients need.
#include "plane_problem.h"

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

struct MultigridLevel {
    CsrMatrix a;                   // the level's operator: A on the finest, Galerkin products below
    std::vector<double> smoother;  // omega / a_ii
    CsrMatrix prolong;             // this level's rows, the next level's columns
    CsrMatrix restrict_;           // prolong transposed
};

struct PlaneMultigrid {
    std::vector<MultigridLevel> levels;  // the smoothed levels, finest first (none for tiny problems)
    CsrMatrix coarsest;                  // the operator of the dense level
    std::vector<double> coarsest_inverse;  // row-major, coarsest.rows() squared
    std::size_t coarsest_rows() const { return coarsest.rows(); }
    const CsrMatrix& finest() const { return levels.empty() ? coarsest : levels.front().a; }
    std::size_t rows() const { return finest().rows(); }
};

// Levels are coarsened until at most this many rows are left, which are solved densely.
inline constexpr std::size_t kMultigridDenseRows = 256;

// Throws gimg::Error (InvalidArgument) when aggregation stalls above 1024 rows (a matrix almost
// without off-diagonal entries), which the cotangent Laplacian of a connected mesh cannot be; the
// polish is then not kept, with the message in the map's note.
PlaneMultigrid build_plane_multigrid(const PlaneProblem& problem);

// z = V-cycle(b).
std::vector<glm::dvec2> apply_multigrid_cpu(const PlaneMultigrid& mg, const std::vector<glm::dvec2>& b);

}  // namespace gimg::passes::detail

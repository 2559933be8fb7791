#pragma once
// Discrete mean and Gaussian curvature per vertex, as seed paper 003 eq. (6.11)-(6.12) uses them
// (citing Desbrun et al. 1999 and Garimella & Swartz 2003):
//
//   H_i = 1 / (4 A_i) || sum_{j in N(i)} (cot alpha_j + cot beta_j) (x_i - x_j) ||
//   K_i = (2 pi - sum_j theta_j) / A_i                    (angle defect)
//   k1^2 + k2^2 = 4 H_i^2 - 2 K_i
//
// The paper leaves the area A_i (its "A_i 3D") unnamed; the formula is only consistent (H = 1/r
// on a sphere) with the mixed Voronoi area of Meyer et al. 2003, which is what we use.

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/mesh.h"

#include <cstdint>
#include <vector>

namespace gimg::geo {

struct VertexCurvature {
    // Mean curvature H. Its magnitude is the paper's H_i; the sign is that of the mean-curvature
    // vector along the angle-weighted vertex normal: positive where the surface bends away from
    // its normal, so +1/r on a sphere with outward (counter-clockwise) faces.
    std::vector<double> mean;
    // Gaussian curvature K: angle defect over mixed area. Gauss-Bonnet holds exactly for the
    // defects: sum_i K_i A_i = 2 pi chi on a closed mesh.
    std::vector<double> gaussian;
    // k1^2 + k2^2 = 4 H^2 - 2 K, clamped at 0 (discrete H and K are not always consistent).
    std::vector<double> principal_square_sum;
    // 1 where the formulas above apply: the vertex's faces form one closed fan with two faces on
    // every edge (see MeshAdjacency::interior_vertices).
    std::vector<std::uint8_t> interior;
};

// At non-interior vertices (boundary, non-manifold, isolated) the one-ring formulas do not hold.
// Following the paper (6.5.3: boundary vertices take the mean of k1^2 + k2^2 over N(i)), each of
// the three fields there is the mean of its values at the *interior* one-ring neighbours (the
// boundary neighbours have no value of their own), or 0 when there is none. Interior vertices
// whose mixed area is 0 (all faces degenerate) get 0.
VertexCurvature compute_curvature(const Mesh& mesh, const MeshAdjacency& adjacency);

}  // namespace gimg::geo

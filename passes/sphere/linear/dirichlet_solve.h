#pragma once
// One sparse direct solve shared by both linear steps of the `linear` spherical map: a symmetric
// positive (semi)definite stiffness matrix over all vertices, some vertices pinned to prescribed
// points of the complex plane, the others solved for. Both coordinates share one factorisation.

#include <complex>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gimg::passes::linear_sphere {

// Entries (row, col, value) of a symmetric matrix; repeated entries add up. Both (i, j) and
// (j, i) must be given for an off-diagonal pair.
struct StiffnessEntry {
    std::uint32_t row, col;
    double value;
};

struct DirichletSolution {
    std::vector<std::complex<double>> z;  // one per vertex; pinned ones keep their value
    bool ok = false;
    std::string why;  // what failed when !ok
};

// Solves K_ff z_f = -K_fp z_p for the free vertices f (pinned[v] == 0), with z_p = pinned_values
// at the pinned ones. Fails (ok = false) when the factorisation fails or the result is not finite.
DirichletSolution solve_dirichlet(std::size_t vertex_count, const std::vector<StiffnessEntry>& stiffness,
                                  const std::vector<std::uint8_t>& pinned,
                                  const std::vector<std::complex<double>>& pinned_values);

}  // namespace gimg::passes::linear_sphere

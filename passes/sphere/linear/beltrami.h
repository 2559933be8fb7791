#pragma once
// Beltrami coefficients and the linear Beltrami solver (Lui et al.), the tools of the south-pole
// step of the `linear` spherical map.
//
// A map f of the plane has Beltrami coefficient mu = f_zbar / f_z; it is conformal where mu = 0.
// If a triangulation of the plane carries the mesh's metric (each planar triangle stands for a
// mesh triangle), mu of the piecewise-affine map "plane -> mesh" says how far the planar layout
// is from conformal. A map g of the plane with the same mu then makes g o (plane -> mesh)^-1,
// the composite mesh -> plane, conformal: the linear Beltrami solver finds that g.
//
// Worth knowing when reading results: with mu taken against the mesh's own metric, the solver's
// matrix is each triangle's Dirichlet energy in that metric, which is the mesh's cotangent
// Laplacian. The correction is therefore a cotangent harmonic map with new pinned vertices (a
// test holds the two to round-off), and it inherits that map's weak spots: negative weights at
// obtuse angles, and precision lost where the layout squeezes a region to nothing.

#include "sphere/linear/dirichlet_solve.h"

#include "gimg/geometry/mesh.h"

#include <complex>
#include <cstdint>
#include <string>
#include <vector>

namespace gimg::passes::linear_sphere {

// Per face where `faces[f]` is set: mu of the affine map from the planar triangle (plane[a],
// plane[b], plane[c]) onto the mesh triangle, computed from the pulled-back metric
// E, F, G: mu = (E - G + 2iF) / (E + G + 2 sqrt(EG - F^2)). The metric does not see orientation;
// this is the coefficient of the orientation-preserving map with that metric, |mu| < 1.
// Other faces get 0. A planar triangle of zero area gives NaN (it has no metric to pull back).
std::vector<std::complex<double>> beltrami_coefficients(const geo::Mesh& mesh,
                                                        const std::vector<std::complex<double>>& plane,
                                                        const std::vector<std::uint8_t>& faces);

// Linear Beltrami solver: the map g of the planar triangulation `plane` (the mesh's connectivity)
// with Beltrami coefficient mu on the faces touching a free vertex, g = pinned_values at the
// pinned vertices. g = u + iv with mu = rho + i tau solves div(A grad u) = div(A grad v) = 0 for
//   A = 1 / (1 - |mu|^2) [ |1 - mu|^2   -2 tau      ]
//                        [ -2 tau       |1 + mu|^2  ],
// discretised with linear elements on the planar triangles (mu = 0 gives the cotangent Laplacian).
// Fails with a reason when a needed face has a non-finite mu, |mu| >= 1 or zero planar area.
DirichletSolution linear_beltrami_solve(const geo::Mesh& mesh, const std::vector<std::complex<double>>& plane,
                                        const std::vector<std::complex<double>>& mu,
                                        const std::vector<std::uint8_t>& pinned,
                                        const std::vector<std::complex<double>>& pinned_values);

}  // namespace gimg::passes::linear_sphere

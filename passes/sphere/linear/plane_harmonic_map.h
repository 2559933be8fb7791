#pragma once
// North-pole step of the `linear` spherical map (Choi, Lam & Lui): take one "big triangle" out of
// the closed mesh, which leaves a disk, and map that disk into the plane by a harmonic map whose
// boundary is the big triangle itself laid flat with its own shape.

#include "sphere/linear/dirichlet_solve.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/mesh.h"

#include <array>
#include <complex>
#include <cstdint>
#include <vector>

namespace gimg::passes::linear_sphere {

// The face closest to equilateral (smallest sum over its edges of |edge / perimeter - 1/3|), the
// paper's choice: a well-shaped boundary keeps the harmonic map's distortion near it small.
std::uint32_t most_regular_face(const geo::Mesh& mesh);

// The corners of face `big` laid flat: a at 0, b at 1, c at the angle of corner a and the length
// ratio |ac| / |ab|, below the real axis (the mirror image, see harmonic_map_to_plane).
std::array<std::complex<double>, 3> flat_big_triangle(const geo::Mesh& mesh, std::uint32_t big);

// Harmonic map of the mesh minus face `big` for the given edge weights (cotangent weights for the
// paper's map, all ones for a Tutte embedding), the three corners of `big` pinned to a similar
// copy of it with unit first edge. The copy is mirrored so that every other face comes out
// counter-clockwise: seen from the disk, the big triangle's boundary runs the other way round.
// The result is translated so that the vertices' mean is 0.
DirichletSolution harmonic_map_to_plane(const geo::Mesh& mesh, const geo::MeshAdjacency& adjacency,
                                        const std::vector<double>& edge_weights, std::uint32_t big);

// The face other than `big` whose corners' distances from the origin of the plane map `w` sum
// least (where the south pole goes); the face count when there is none.
std::size_t face_nearest_origin(const geo::Mesh& mesh, const std::vector<std::complex<double>>& w, std::uint32_t big);

// Scale for the plane map `w` (big triangle at infinity) so that the big triangle and the face
// nearest the origin come out the same size on the sphere: the big triangle's mean edge in the
// chart w and the inner face's mean edge in the chart 1 / w meet at their geometric mean. 1 when
// either size is unusable.
double balancing_scale(const geo::Mesh& mesh, const std::vector<std::complex<double>>& w, std::uint32_t big);

// sum over edges of weight * |z(u) - z(v)|^2: the Dirichlet energy the harmonic map minimises.
double dirichlet_energy(const geo::MeshAdjacency& adjacency, const std::vector<double>& edge_weights,
                        const std::vector<std::complex<double>>& z);

}  // namespace gimg::passes::linear_sphere

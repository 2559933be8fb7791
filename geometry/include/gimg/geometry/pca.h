#pragma once
// Principal-axis alignment as seed paper 003, section 2.5.1 and appendix A.2: the covariance of
// the model's points (A.2.1), its eigenvectors sorted by eigenvalue (A.2.2), and a rotation built
// from the first two axes with the third as their cross product so the model is never mirrored
// (A.2.4, eq. A.9). The main axis becomes +y (the cylinder axis of DESIGN.md's units).

#include "gimg/geometry/mesh.h"
#include "gimg/geometry/rigid_transform.h"

#include <glm/vec3.hpp>

namespace gimg::geo {

enum class PcaWeighting {
    // The paper's choice (A.2.1, fig. A.1 d-f): every vertex is one sample, equally weighted.
    // Follows the tessellation: densely meshed parts pull the axes towards them.
    Vertices,
    // Uniform density over the surface (exact integrals over each triangle): independent of how
    // the surface is tessellated. Not in the paper; offered for meshes with very uneven density.
    SurfaceArea,
};

struct PcaAlignment {
    // Maps the input into the aligned frame: centroid to the origin, main axis to +y, second axis
    // to +x, third to +z. det(rotation) = +1 always. transform.inverse() maps back.
    RigidTransform transform;
    glm::dvec3 centroid{0.0};
    // Unit principal axes in the input frame (the rows of transform.rotation): main, second, and
    // third = second x main (right-handed with x = second, y = main).
    glm::dvec3 main_axis{0.0, 1.0, 0.0};
    glm::dvec3 second_axis{1.0, 0.0, 0.0};
    glm::dvec3 third_axis{0.0, 0.0, 1.0};
    // Variances along main, second and third axis (descending eigenvalues of the covariance).
    glm::dvec3 variances{0.0};
};

// Sign of each axis (an eigenvector is only defined up to sign): the main and second axes point
// towards the positive third central moment (skewness) of the samples projected on them, i.e.
// towards the longer tail of the distribution. When that moment is negligible (|m3| <= 1e-6 sigma^3,
// a symmetric shape, e.g. a box) the axis instead points so that its largest-magnitude component
// (first such component on ties) is positive. The third axis' sign is never chosen: it is the
// cross product, which is what rules out mirroring. Degenerate inputs (no samples, all samples
// equal) give the identity rotation about the centroid.
PcaAlignment compute_pca_alignment(const Mesh& mesh, PcaWeighting weighting = PcaWeighting::Vertices);

}  // namespace gimg::geo

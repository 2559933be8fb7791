#pragma once
// A rigid motion p -> R p + t (R a rotation, det R = +1), applied to points, directions and
// meshes, and inverted exactly (R^T), so results computed in an aligned frame can be carried back
// to the input's frame.

#include "gimg/geometry/mesh.h"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace gimg::geo {

struct RigidTransform {
    glm::dmat3 rotation{1.0};  // column-major (glm): rotation * p
    glm::dvec3 translation{0.0};

    glm::dvec3 apply_point(const glm::dvec3& p) const { return rotation * p + translation; }
    // Directions and normals: rotation only (a rotation maps normals like vectors).
    glm::dvec3 apply_vector(const glm::dvec3& v) const { return rotation * v; }

    // p -> R^T (p - t).
    RigidTransform inverse() const;
    // (*this) after `first`: p -> this(first(p)).
    RigidTransform after(const RigidTransform& first) const;

    // Copy of `mesh` with every position moved; triangles and texcoords unchanged (a proper
    // rotation keeps the counter-clockwise orientation).
    Mesh apply(const Mesh& mesh) const;
    void apply_in_place(Mesh& mesh) const;
};

}  // namespace gimg::geo

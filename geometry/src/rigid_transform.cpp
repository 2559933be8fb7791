#include "gimg/geometry/rigid_transform.h"

#include <glm/matrix.hpp>

namespace gimg::geo {

RigidTransform RigidTransform::inverse() const {
    const glm::dmat3 rt = glm::transpose(rotation);
    return {rt, -(rt * translation)};
}

RigidTransform RigidTransform::after(const RigidTransform& first) const {
    return {rotation * first.rotation, rotation * first.translation + translation};
}

Mesh RigidTransform::apply(const Mesh& mesh) const {
    Mesh out = mesh;
    apply_in_place(out);
    return out;
}

void RigidTransform::apply_in_place(Mesh& mesh) const {
    for (glm::dvec3& p : mesh.positions) p = apply_point(p);
}

}  // namespace gimg::geo

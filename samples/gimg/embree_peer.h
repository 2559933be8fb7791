#pragma once
// Intel Embree casting the cylindrical image's rays with the same facing rule: the CPU peer a user
// would pick today, timed beside gimg's methods by `gimg bench cylinder`. Built only when Debian's
// libembree-dev is present (GIMG_HAS_EMBREE).

#include "gimg/passes/cylinder.h"

#include <memory>

namespace gimg::cli {

bool embree_available();

class EmbreeCylinderCaster {
public:
    // Builds Embree's BVH over the mesh (in the cylinder frame).
    explicit EmbreeCylinderCaster(const passes::CylinderMesh& mesh);
    ~EmbreeCylinderCaster();
    EmbreeCylinderCaster(const EmbreeCylinderCaster&) = delete;
    EmbreeCylinderCaster& operator=(const EmbreeCylinderCaster&) = delete;
    // One ray per pixel from the wall towards the axis, nearest hit on a triangle facing it.
    passes::CylinderImage project(std::uint32_t width, std::uint32_t height) const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace gimg::cli

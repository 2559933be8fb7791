#include "gimg/geometry/mesh.h"

#include <glm/geometric.hpp>
#include <glm/common.hpp>

namespace gimg::geo {

double Bounds::diagonal() const { return glm::length(max - min); }

Bounds Mesh::bounds() const {
    if (positions.empty()) return {};
    Bounds b{positions.front(), positions.front()};
    for (const glm::dvec3& p : positions) {
        b.min = glm::min(b.min, p);
        b.max = glm::max(b.max, p);
    }
    return b;
}

}  // namespace gimg::geo

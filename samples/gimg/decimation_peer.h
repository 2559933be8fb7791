#pragma once
// The yardstick `gimg bench maps` sets beside each remesh level: OpenMesh's decimater with its
// quadric module (Garland-Heckbert halfedge collapses, vertices kept at their places), any genus.
#include "gimg/geometry/mesh.h"

#include <cstddef>

namespace gimg::cli {

// The mesh decimated to (at most) `vertices` vertices; fewer collapses when the topology stops them.
geo::Mesh quadric_decimation(const geo::Mesh& mesh, std::size_t vertices);

}  // namespace gimg::cli

#pragma once
// The coarse-to-fine meshes that Kanai's method and the harmonic method's fallback walk through:
// a progressive mesh of the input (gimg/geometry/progressive_mesh.h), checked for a sphere first.
#include "gimg/geometry/mesh.h"
#include "gimg/geometry/progressive_mesh.h"

#include <cstddef>
#include <vector>

namespace gimg::passes::detail {

// check_sphere_input (throws geo::InputError on an unfit mesh) + build_progressive_mesh +
// hierarchy_levels.
std::vector<geo::HierarchyLevel> build_sphere_hierarchy(const geo::Mesh& mesh, std::size_t base_vertices,
                                                        double growth);

}  // namespace gimg::passes::detail

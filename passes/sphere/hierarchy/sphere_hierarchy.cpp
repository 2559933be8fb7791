// A sphere's progressive-mesh hierarchy, after the input check.
#include "sphere/hierarchy/sphere_hierarchy.h"

#include "gimg/passes/sphere.h"

namespace gimg::passes::detail {

std::vector<geo::HierarchyLevel> build_sphere_hierarchy(const geo::Mesh& mesh, std::size_t base_vertices,
                                                        double growth) {
    check_sphere_input(mesh);
    return geo::hierarchy_levels(geo::build_progressive_mesh(mesh, base_vertices), growth);
}

}  // namespace gimg::passes::detail

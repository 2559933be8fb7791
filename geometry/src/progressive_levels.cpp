// Intermediate meshes of a progressive mesh, without replaying it: with halfedge collapses a face
// of the full mesh, at a given vertex count, has as corners the nearest active ancestors of its
// original corners, and it exists there exactly when those three are distinct.
#include "gimg/geometry/progressive_mesh.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace gimg::geo {

namespace {

// Vertices in activation order (the inverse of activation_order()).
std::vector<std::uint32_t> activation_sequence(const ProgressiveMesh& pm) {
    std::vector<std::uint32_t> order(pm.coarsest_vertices);
    order.reserve(pm.vertex_count);
    for (const VertexSplit& s : pm.splits) order.push_back(s.vertex);
    return order;
}

}  // namespace

std::vector<std::uint32_t> activation_order(const ProgressiveMesh& pm) {
    const std::vector<std::uint32_t> order = activation_sequence(pm);
    std::vector<std::uint32_t> index(pm.vertex_count, 0);
    for (std::uint32_t i = 0; i < order.size(); ++i) index[order[i]] = i;
    return index;
}

std::vector<glm::uvec3> triangles_at(const ProgressiveMesh& pm, std::size_t active_count) {
    const std::vector<std::uint32_t> order = activation_sequence(pm);
    // rep[v]: v itself when active, else the representative of the vertex it was split from, which
    // became active earlier and so is already known when walking in activation order.
    std::vector<std::uint32_t> rep(pm.vertex_count, 0);
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::uint32_t v = order[i];
        rep[v] = i < active_count || i < pm.coarsest_count() ? v : rep[pm.splits[i - pm.coarsest_count()].parent];
    }
    std::vector<glm::uvec3> out;
    for (const glm::uvec3& t : pm.triangles) {
        const glm::uvec3 r(rep[t.x], rep[t.y], rep[t.z]);
        if (r.x != r.y && r.y != r.z && r.z != r.x) out.push_back(r);
    }
    return out;
}

std::vector<std::size_t> level_vertex_counts(std::size_t base, std::size_t total, double growth) {
    if (!(growth > 1.0) || !std::isfinite(growth))
        throw geo::InputError("hierarchy growth must be a number greater than 1 (got " + std::to_string(growth) + ")");
    std::vector<std::size_t> counts{std::min(base, total)};
    while (counts.back() < total) {
        const double next = std::round(double(counts.back()) * growth);
        counts.push_back(std::min(total, std::max(counts.back() + 1, std::size_t(std::min(next, double(total))))));
    }
    return counts;
}

std::vector<HierarchyLevel> hierarchy_levels(const ProgressiveMesh& pm, double growth) {
    const std::vector<std::uint32_t> order = activation_sequence(pm);
    std::vector<HierarchyLevel> levels;
    std::size_t previous = 0;
    for (std::size_t count : level_vertex_counts(pm.base_vertex_count, pm.vertex_count, growth)) {
        HierarchyLevel level;
        level.triangles = triangles_at(pm, count);
        level.vertices.assign(order.begin(), order.begin() + std::ptrdiff_t(count));
        if (!levels.empty())
            for (std::size_t i = previous; i < count; ++i) {
                level.added.push_back(order[i]);
                level.parent.push_back(pm.splits[i - pm.coarsest_count()].parent);
            }
        levels.push_back(std::move(level));
        previous = count;
    }
    return levels;
}

}  // namespace gimg::geo

// A laid-out level's mesh checked for a spherical parameterization (relaxation_mesh_check.h says why
// this is enough).
#include "sphere/harmonic/relaxation_mesh_check.h"

#include "gimg/geometry/parallel_for.h"
#include "gimg/geometry/topology.h"

#include <atomic>
#include <numeric>

namespace gimg::passes::detail {

namespace {

// Components of the level's vertex graph, by union-find with path halving.
std::size_t component_count(const RelaxationMesh& level) {
    const std::size_t n = level.vertex_count();
    std::vector<std::uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (std::uint32_t v = 0; v < n; ++v)
        for (std::uint32_t k = level.ring_offsets[v]; k < level.ring_offsets[v + 1]; ++k) {
            const std::uint32_t a = find(v), b = find(level.ring[k]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    std::size_t roots = 0;
    for (std::uint32_t v = 0; v < n; ++v) roots += parent[v] == v;
    return roots;
}

}  // namespace

bool relaxation_mesh_is_sphere(const geo::Mesh& mesh, const RelaxationMesh& level) {
    if (mesh.face_count() < 4 || level.vertex_count() != mesh.vertex_count()) return false;
    std::atomic<bool> degenerate{false};
    geo::parallel_for_chunks(mesh.face_count(), kLevelChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t f = begin; f < end && !degenerate; ++f) {
            const glm::uvec3 t = mesh.triangles[f];
            if (t.x == t.y || t.y == t.z || t.x == t.z || geo::zero_area_face(mesh, t)) degenerate = true;
        }
    });
    if (degenerate) return false;
    // Every edge is a spoke at both its ends, once each (the fans are closed and manifold).
    const std::size_t edges = level.ring.size() / 2;
    const auto euler = std::int64_t(level.vertex_count()) - std::int64_t(edges) + std::int64_t(mesh.face_count());
    return euler == 2 && component_count(level) == 1;
}

}  // namespace gimg::passes::detail

// Vertex splits applied one by one on per-vertex face lists.
#include "gimg/geometry/progressive_replay.h"

#include <algorithm>
#include <stdexcept>

namespace gimg::geo {

ProgressiveReplay::ProgressiveReplay(const ProgressiveMesh& pm, std::size_t active_count)
    : pm_(pm), active_(std::clamp(active_count, pm.coarsest_count(), pm.vertex_count)), tri_(pm.triangles),
      alive_(pm.triangles.size(), 0), vfaces_(pm.vertex_count) {
    // The same nearest-active-ancestor rule as triangles_at(), kept per face id here.
    const std::vector<std::uint32_t> index = activation_order(pm);
    std::vector<std::uint32_t> order(pm.vertex_count);
    for (std::uint32_t v = 0; v < pm.vertex_count; ++v) order[index[v]] = v;
    std::vector<std::uint32_t> rep(pm.vertex_count);
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::uint32_t v = order[i];
        rep[v] = i < active_ ? v : rep[pm.splits[i - pm.coarsest_count()].parent];
    }
    for (std::uint32_t f = 0; f < tri_.size(); ++f) {
        const glm::uvec3 t = pm.triangles[f];
        tri_[f] = glm::uvec3(rep[t.x], rep[t.y], rep[t.z]);
        const glm::uvec3& r = tri_[f];
        if (r.x == r.y || r.y == r.z || r.z == r.x) continue;
        alive_[f] = 1;
        for (int k = 0; k < 3; ++k) vfaces_[r[k]].push_back(f);
    }
}

const VertexSplit& ProgressiveReplay::split_next() {
    if (complete()) throw std::logic_error("ProgressiveReplay::split_next past the full mesh");
    const VertexSplit& s = pm_.splits[active_ - pm_.coarsest_count()];
    for (std::uint32_t i = s.moved_begin; i < s.moved_end; ++i) {
        const std::uint32_t f = pm_.moved_faces[i];
        for (int k = 0; k < 3; ++k)
            if (tri_[f][k] == s.parent) tri_[f][k] = s.vertex;
        auto& list = vfaces_[s.parent];
        list.erase(std::find(list.begin(), list.end(), f));
        vfaces_[s.vertex].push_back(f);
    }
    for (int i = 0; i < 2; ++i) {
        const std::uint32_t f = s.born_faces[i];
        tri_[f] = s.born_triangles[i];
        alive_[f] = 1;
        for (int k = 0; k < 3; ++k) vfaces_[tri_[f][k]].push_back(f);
    }
    ++active_;
    return s;
}

std::vector<glm::uvec3> ProgressiveReplay::live_triangles() const {
    std::vector<glm::uvec3> out;
    for (std::uint32_t f = 0; f < tri_.size(); ++f)
        if (alive_[f]) out.push_back(tri_[f]);
    return out;
}

}  // namespace gimg::geo

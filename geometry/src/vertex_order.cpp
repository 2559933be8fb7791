// Spatial vertex renumbering along a Morton curve.
#include "gimg/geometry/vertex_order.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

namespace gimg::geo {

namespace {

constexpr int kBitsPerAxis = 21;  // 3 x 21 bits fit a 64-bit key

// x's low 21 bits spread to every third bit.
std::uint64_t spread_bits(std::uint64_t x) {
    std::uint64_t out = 0;
    for (int b = 0; b < kBitsPerAxis; ++b) out |= ((x >> b) & 1u) << (3 * b);
    return out;
}

}  // namespace

std::vector<std::uint32_t> spatial_vertex_order(const Mesh& mesh) {
    const Bounds box = mesh.bounds();
    const double cells = double((1u << kBitsPerAxis) - 1);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(mesh.vertex_count());
    for (std::uint32_t v = 0; v < keyed.size(); ++v) {
        std::uint64_t key = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const double extent = box.max[axis] - box.min[axis];
            const double t = extent > 0.0 ? (mesh.positions[v][axis] - box.min[axis]) / extent : 0.0;
            // Non-finite coordinates (rejected elsewhere) land in cell 0 rather than overflow.
            const double cell = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) * cells : 0.0;
            key |= spread_bits(std::uint64_t(cell)) << axis;
        }
        keyed[v] = {key, v};
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> order(keyed.size());
    for (std::size_t k = 0; k < keyed.size(); ++k) order[k] = keyed[k].second;
    return order;
}

Mesh reorder_vertices(const Mesh& mesh, const std::vector<std::uint32_t>& order) {
    // out[k] = values[order[k]]; empty (absent) attributes stay empty.
    auto gathered = [&order](const auto& values) {
        std::remove_cvref_t<decltype(values)> out;
        if (values.size() != order.size()) return out;
        out.reserve(order.size());
        for (std::uint32_t old : order) out.push_back(values[old]);
        return out;
    };
    std::vector<std::uint32_t> new_index(mesh.vertex_count());
    for (std::uint32_t k = 0; k < order.size(); ++k) new_index[order[k]] = k;
    Mesh out;
    out.positions = gathered(mesh.positions);
    out.texcoords = gathered(mesh.texcoords);
    out.normals = gathered(mesh.normals);
    out.triangles.reserve(mesh.face_count());
    for (const glm::uvec3& t : mesh.triangles) out.triangles.push_back({new_index[t.x], new_index[t.y], new_index[t.z]});
    return out;
}

}  // namespace gimg::geo

#include "gimg/geometry/weld.h"

#include <bit>
#include <cstdint>
#include <unordered_map>

namespace gimg::geo {

namespace {

struct PositionKey {
    std::uint64_t x, y, z;
    bool operator==(const PositionKey&) const = default;
};

struct PositionHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
        h ^= (k.y + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2));
        h ^= (k.z + 0x94D049BB133111EBull + (h << 6) + (h >> 2));
        return static_cast<std::size_t>(h);
    }
};

// +0.0 and -0.0 are the same position.
std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v == 0.0 ? 0.0 : v); }

}  // namespace

std::size_t weld_identical_vertices(Mesh& mesh) {
    const std::size_t n = mesh.positions.size();
    std::unordered_map<PositionKey, std::uint32_t, PositionHash> first;
    first.reserve(n);
    std::vector<std::uint32_t> remap(n);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3& p = mesh.positions[i];
        const auto [it, inserted] =
            first.try_emplace({bits(p.x), bits(p.y), bits(p.z)}, static_cast<std::uint32_t>(kept));
        if (inserted) {
            mesh.positions[kept] = p;
            if (mesh.has_texcoords()) mesh.texcoords[kept] = mesh.texcoords[i];
            ++kept;
        }
        remap[i] = it->second;
    }
    const bool texcoords = mesh.has_texcoords();
    mesh.positions.resize(kept);
    if (texcoords) mesh.texcoords.resize(kept);
    for (glm::uvec3& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            if (t[k] < n) t[k] = remap[t[k]];
        }
    }
    return n - kept;
}

}  // namespace gimg::geo

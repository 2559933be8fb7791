#pragma once
// Where a level's rays start and which way they point, from the previous level's grid (the
// thesis, 3.3): the encoder and the decoder compute them alike, the decoder from decoded points.
#include "gimg/passes/cylinder_hierarchy.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

struct Launch {
    glm::dvec3 origin{0.0};
    glm::dvec3 normal{0.0};  // unit, outward (away from the material)
    double span = 0.0;       // the largest distance between its parents
    std::uint8_t valid = 0;  // every parent valid (and, for V and D, not the last row)
    std::int8_t outward = 1;
};

// For a grid of side S: H (S x S, between (u, v) and (u + 1, v), u wrapping), V and D (S x S,
// between rows v and v + 1 and the cell centres; the last row invalid), row-major.
struct LevelLaunches {
    std::vector<Launch> h, v, d;
};
LevelLaunches level_launches(const HierarchyGrid& grid);

// The next grid (side 2S): G'[2v][2u] = G[v][u], G'[2v][2u + 1] = H, G'[2v + 1][2u] = V,
// G'[2v + 1][2u + 1] = D, each new point origin + t normal where valid.
HierarchyGrid interleave(const HierarchyGrid& grid, const LevelLaunches& launches, const std::vector<float>& th,
                         const std::vector<float>& tv, const std::vector<float>& td,
                         const std::vector<std::uint8_t>& hit_h, const std::vector<std::uint8_t>& hit_v,
                         const std::vector<std::uint8_t>& hit_d);

// Level 1 from its band: t = 1 - d along the inward radial ray of pixel (u, v) of a B x B image.
HierarchyGrid level_one_grid(std::uint32_t base, const std::vector<float>& t, const std::vector<std::uint8_t>& valid);

// Throws geo::InputError unless `level` of `h` can be decoded (sizes, arrays, 1 <= level <= levels).
void check_decodable(const CylinderHierarchy& h, std::uint32_t level);

// Band origins of level L >= 2 in the N x N image (the level's side S = B 2^(L - 2)).
struct Bands {
    std::uint32_t side;  // S
    std::size_t h(std::uint32_t u, std::uint32_t v, std::uint32_t n) const { return std::size_t(v) * n + side + u; }
    std::size_t v(std::uint32_t u, std::uint32_t v, std::uint32_t n) const { return std::size_t(side + v) * n + u; }
    std::size_t d(std::uint32_t u, std::uint32_t v, std::uint32_t n) const {
        return std::size_t(side + v) * n + side + u;
    }
};

}  // namespace gimg::passes::detail

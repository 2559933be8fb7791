#pragma once
// Where a level's rays start and which way they point, from the previous level's grid (the
// thesis, 3.3): the encoder and the decoder compute them alike, the decoder from decoded points.
#include "gimg/passes/cylinder_hierarchy.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

struct Launch {
    glm::dvec3 origin{0.0};
    glm::dvec3 normal{0.0};  // unit, outward (away from the material)
    double span = 0.0;       // the largest distance between its parents
    std::uint8_t valid = 0;  // cast: every parent valid, or a radial ray (below)
    std::int8_t outward = 1;
    // A sample whose parents are not all valid (beside or beyond a level-1 pixel that saw nothing:
    // a model's ends, thin parts) is cast as the ordinary image's ray at its own angle and height,
    // from the wall towards the axis: origin on the wall, normal the inward direction, the value
    // the distance from the wall, as level 1.
    std::uint8_t radial = 0;
};

// A point's distance from the axis, sqrt(x^2 + z^2) (the GPU passes compute it alike).
double radius(const glm::dvec3& p);

// The height of row j of a grid of side `side` (level 1's side `base`; 0 means side): 1 - (j B /
// side + 0.5) / B, plus 1 where that is not above the bottom (the wrapped rows).
double row_height(std::uint32_t j, std::uint32_t side, std::uint32_t base);
// Whether rows v and v + 1 (mod side) are neighbours: the one lies above the other, not across the
// seam between the bottom and the wrapped rows.
bool rows_adjacent(std::uint32_t v, std::uint32_t side, std::uint32_t base);

// For a grid of side S: H (S x S, between (u, v) and (u + 1, v), u wrapping), V and D (S x S,
// between rows v and v + 1 (mod S) and the cell centres; radial across the seam), row-major.
struct LevelLaunches {
    std::vector<Launch> h, v, d;
    std::vector<std::array<double, 2>> directions;  // radial_directions of the next grid (side 2S)
};
// (cos, sin) of the angle of every column of a grid of side `side`: 2 pi (i B / side + 0.5) / B.
std::vector<std::array<double, 2>> radial_directions(std::uint32_t side, std::uint32_t base);

// The radial launch at a column's direction and a row's height (invalid unless the height lies
// strictly within the cylinder's).
Launch radial_launch(const std::array<double, 2>& direction, double y);

// `base` is level 1's side B, which places a radial sample at its angle and height.
LevelLaunches level_launches(const HierarchyGrid& grid, std::uint32_t base);

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

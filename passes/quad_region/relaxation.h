#pragma once
// Eq. (2) of Kuriyama & Kaneko as Gauss-Seidel sweeps in colour order, on the GPU (one workgroup per
// field, one dispatch per chunk of sweeps) and its CPU twin (the same rows in the same order, the
// same rounding). Sweeps run in
// chunks of kSweepsPerCheck; the count returned is the first sweep whose largest correction (as a
// float) is below tau, the map the one after that chunk. With tau = 0 they run max_sweeps (rounded
// up to whole chunks) with no stopping rule, and return that count.

#include "gimg/engine/context.h"
#include "gimg/geometry/adjacency.h"
#include "quad_region/relax_layout.h"

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

inline constexpr std::uint32_t kSweepsPerCheck = GIMG_RELAX_SWEEPS;

// The free rows ordered by colour, then vertex: rows [first[c], first[c + 1]) have colour c.
struct ColouredRows {
    std::vector<std::uint32_t> vertex;   // per row
    std::vector<std::uint32_t> offsets;  // rows + 1: row r's entries are [offsets[r], offsets[r + 1])
    std::vector<std::uint32_t> columns;
    std::vector<double> weights;
    std::vector<std::uint32_t> first;
    std::uint32_t colour_count() const;
};

ColouredRows colour_rows(const geo::MeshAdjacency& adj, const std::vector<double>& weights,
                         const std::vector<std::uint8_t>& interior);

std::size_t relax_cpu(const ColouredRows& rows, double k, double tau, std::size_t max_sweeps,
                      std::vector<glm::dvec2>& uv, int field);
// Both fields at once; the sweep count of each.
std::array<std::size_t, 2> relax_gpu(Context& ctx, const ColouredRows& rows, double k, double tau,
                                     std::size_t max_sweeps, std::vector<glm::dvec2>& uv);

}  // namespace gimg::passes::detail

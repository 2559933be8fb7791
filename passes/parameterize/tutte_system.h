#pragma once
// The weighted Tutte system of a disk with its boundary fixed (eq. 6.4 of the thesis, eq. 1 of
// Kuriyama & Kaneko): u_i - sum_j w_ij u_j = 0 on interior rows (weights normalised per row),
// u_i = fixed on boundary rows; two right-hand sides (u, v).

#include "gimg/geometry/adjacency.h"
#include "gimg/passes/solvers.h"

#include <glm/vec2.hpp>

#include <vector>

namespace gimg::passes::detail {

// weights[k] belongs to adjacency.vertex_vertices[k]; `start` empty or one per vertex.
LinearSystem tutte_system(const geo::MeshAdjacency& adj, const std::vector<double>& weights,
                          const std::vector<std::uint8_t>& interior, const std::vector<glm::dvec2>& fixed_uv,
                          const std::vector<glm::dvec2>& start);

}  // namespace gimg::passes::detail

#pragma once
// How far a boundary loop turns at each of its vertices: where the square map's corners go best.

#include "gimg/geometry/mesh.h"

#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

// Per loop position, the angle between the chords to the loop points a 32nd of the perimeter before
// and after it (nearest vertices), so that a zigzag of single edges does not count.
std::vector<double> boundary_turning(const geo::Mesh& mesh, const std::vector<std::uint32_t>& loop);

}  // namespace gimg::passes::detail

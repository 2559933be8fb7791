#pragma once
// What repair.cpp and repair_zero_area.cpp share.

#include "gimg/geometry/mesh.h"
#include "gimg/geometry/repair.h"

#include <cstdint>

namespace gimg::geo::detail {

inline constexpr std::uint32_t kNoVertex = 0xffffffffu;

// Appends a copy of vertex v (position, texture coordinate and normal where the mesh has them).
void copy_vertex(Mesh& mesh, std::uint32_t v);

// Step 5 of repair_mesh on a manifold, oriented mesh: flips, drops and collapses that remove faces
// of zero area (report.zero_area_faces, flipped_edges, collapsed_edges, zero_area_left).
void remove_zero_area_faces(Mesh& mesh, RepairReport& report);

}  // namespace gimg::geo::detail

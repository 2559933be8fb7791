#pragma once
// Welding: merging vertices that sit at exactly the same position, as polygon soups (STL, models
// exported per part or per material) need before their topology means anything.

#include "gimg/geometry/mesh.h"

#include <cstddef>

namespace gimg::geo {

// Merges vertices with identical coordinates (bitwise equal, with -0 equal to +0) into the first of
// them and renumbers the triangles; a merged vertex keeps the first one's texture coordinate.
// Triangles that become degenerate are kept. Returns the number of vertices removed.
std::size_t weld_identical_vertices(Mesh& mesh);

}  // namespace gimg::geo

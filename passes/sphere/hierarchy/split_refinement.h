#pragma once
// Replaying vertex splits on the sphere (Kanai, 4.1 and step 2 of 4.4): each split's new vertex is
// placed next to its parent, then the new vertex and the parent get the vertex Tutte optimisation,
// every move kernel-checked, so the map stays one-to-one split after split.

#include "gimg/geometry/progressive_replay.h"

namespace gimg::passes::detail {

struct SplitRun {
    std::size_t splits = 0;
    std::size_t kernel_refusals = 0;     // Tutte steps refused (the vertex kept its place)
    std::size_t placement_failures = 0;  // new vertices left on their parent (should stay 0)
};

// Applies splits until `target` vertices are active. y must hold a flip-free map of the current
// mesh; it then holds one of the refined mesh.
//
// Placement (the paper leaves it open): the two faces a split brings back, (v, parent, left) and
// (parent, v, right), are degenerate with v on its parent. Their orientation grows linearly with
// v's offset d from the parent, with gradients n1, n2 in the tangent plane; d = n1/|n1| + n2/|n2|
// makes both positive, and for a small enough offset every other face around v keeps the positive
// orientation it had around the parent. So v = normalize(parent + eps d), eps halved from a quarter
// of the shortest distance to the neighbours until every face around v is counter-clockwise.
SplitRun split_to(geo::ProgressiveReplay& replay, std::vector<glm::dvec3>& y, std::size_t target);

}  // namespace gimg::passes::detail

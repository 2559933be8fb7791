#pragma once
// How a hierarchy ray is cast (the thesis, 3.3.2, with the spec's fixes), shared by the CPU and
// the GPU encoder:
//  - inside or outside: crossings of the model on the radial segment from the cylinder wall to the
//    launch point (at its angle and height), as TriangleBvh::crossings counts them (a segment
//    through an edge or a corner counts one crossing); odd is inside;
//  - inside fires along the outward normal, outside against it;
//  - the nearest hit with t >= -kBehind (a launch point on a flat patch lies on the surface: its
//    own surface, at t = 0, is the answer, not the far side of the model), at most reach times
//    the distance between its parents away (reach 0: without limit);
//  - the value stored is the signed distance along the outward normal.
#include "launch_rays.h"

#include "gimg/geometry/bvh.h"
#include "gimg/geometry/triangle_queries.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace gimg::passes::detail {

inline constexpr double kBehind = 1e-9;  // in cylinder units (radius 1)

// The radial segment from the wall to the launch point (t in [0, 1]).
geo::Ray parity_segment(const glm::dvec3& origin);
// Odd crossings: inside.
inline bool inside_by_parity(std::uint32_t crossings) { return crossings % 2 == 1; }
// The ray from a launch point, inside firing along the outward normal.
geo::Ray launch_ray(const Launch& l, bool inside, double reach);
// A radial launch's ray: the ordinary image's (from the axis outwards, t in [-1, 1], the nearest
// front face to the wall); its value is 1 + t, the distance from the wall.
geo::Ray radial_ray(const Launch& l);
// A valid launch cast through the CPU BVH by these rules: its value (the signed distance along
// the outward normal, or for a radial launch the distance from the wall), nullopt for a miss.
std::optional<double> cast_launch(const geo::TriangleBvh& bvh, const Launch& l, double reach);

}  // namespace gimg::passes::detail

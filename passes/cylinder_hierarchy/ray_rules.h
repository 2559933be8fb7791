#pragma once
// How a hierarchy ray is cast (the thesis, 3.3.2, with the spec's fixes), shared by the CPU encoder
// and mirrored by the GPU pass:
//  - inside or outside: crossings of the model on the radial segment from the cylinder wall to the
//    launch point (at its angle and height), hits at one t merged so that a segment through an
//    edge or a corner counts one crossing; odd is inside;
//  - inside fires along the outward normal, outside against it;
//  - the nearest hit with t >= -kBehind (a launch point on a flat patch lies on the surface: its
//    own surface, at t = 0, is the answer, not the far side of the model);
//  - a ray goes at most reach times the distance between its parents;
//  - the value stored is the signed distance along the outward normal.
#include "launch_rays.h"

#include "gimg/geometry/bvh.h"

#include <optional>

namespace gimg::passes::detail {

inline constexpr double kBehind = 1e-9;    // in cylinder units (radius 1)
inline constexpr double kSameHit = 1e-12;  // hits closer than this along a segment are one crossing

bool launch_inside(const geo::TriangleBvh& bvh, const glm::dvec3& origin);

// The signed distance along l.normal to the hit, or nullopt when the ray hits nothing within
// reach * l.span (reach 0: without limit).
std::optional<double> cast_from(const geo::TriangleBvh& bvh, const Launch& l, double reach);

}  // namespace gimg::passes::detail

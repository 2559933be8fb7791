#pragma once
// The encoders' hierarchy before its levels, and the CPU encoder's levels.
#include "launch_rays.h"

#include <chrono>
#include <functional>
#include <optional>
#include <vector>

namespace gimg::passes::detail {

// Wall milliseconds since t: the encoders' level times.
inline double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Throws geo::InputError for a reach that is negative or not finite.
void check_reach(double reach);
// The N x N hierarchy, every sample empty, with the options' base, size and reach. Throws
// geo::InputError for a reach that is negative or not finite.
CylinderHierarchy empty_hierarchy(const CylinderHierarchyOptions& options);
// The same with level 1 in place: t = 1 - d of the ordinary B x B image, top-left.
CylinderHierarchy start_hierarchy(const CylinderImage& first, const CylinderHierarchyOptions& options);

// Casts the valid launches of one level (launch_ray, parity included; radial_ray for radial
// ones): the signed distance along each launch's outward normal (for a radial launch the distance
// from the wall), or nullopt for a miss (and for invalid launches).
using CastLevel = std::function<std::vector<std::optional<double>>(const std::vector<Launch>& launches)>;

// Level 1 from the ordinary B x B image (which took first_ms), then every later level through `cast`.
CylinderHierarchy encode_hierarchy(const CylinderImage& first, double first_ms, const CylinderHierarchyOptions& options,
                                   const CastLevel& cast);

}  // namespace gimg::passes::detail

#pragma once
// Area-weighted stratified point sampling of a triangle surface, deterministic from a seed.
//
// Stratification happens twice:
//  - across faces: face f gets floor or ceil of its expected count N * area_f / total_area, by
//    systematic rounding (one random offset u for the whole mesh: count_f = floor(C_f + u) -
//    floor(C_{f-1} + u), C the cumulative expected count), so the total is exactly N and every
//    face's count is within 1 of its share;
//  - within a face: its n points are the first n points of the R2 low-discrepancy sequence
//    (Roberts 2018), shifted by a per-face random offset (Cranley-Patterson rotation) and folded
//    from the unit square onto the triangle (u + v > 1 -> 1 - u, 1 - v), which is uniform by area.
// Every random number is a hash of (seed, face), so a face's points do not depend on which thread
// generates them or in what order.

#include "gimg/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace gimg::geo {

struct SurfaceSamplingOptions {
    // Total number of area samples; 0 means max(min_samples, samples_per_face * faces).
    std::size_t sample_count = 0;
    std::size_t min_samples = 1'000'000;
    std::size_t samples_per_face = 10;
    std::uint64_t seed = 0x9e3779b97f4a7c15ull;
};

// The N the options ask for on a mesh of `faces` faces.
std::size_t resolve_sample_count(const SurfaceSamplingOptions& options, std::size_t faces);

// Samples per face (the systematic rounding above); sums to `total` whenever the mesh has
// positive area (all zeros otherwise). Faces of zero area get none.
std::vector<std::uint32_t> face_sample_counts(const std::vector<double>& face_areas, std::size_t total,
                                              std::uint64_t seed);

// Sample i (0-based) of face `face`, a triangle with corners a, b, c.
glm::dvec3 triangle_sample(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::uint32_t face,
                           std::uint32_t i, std::uint64_t seed);

// All samples of the mesh, face by face (for tests and small meshes; the surface-distance code
// generates them on the fly instead of storing them).
std::vector<glm::dvec3> sample_surface(const Mesh& mesh, const SurfaceSamplingOptions& options = {});

}  // namespace gimg::geo

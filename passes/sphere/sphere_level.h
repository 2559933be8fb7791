#pragma once
// One mesh of the sphere hierarchy, laid out for the relaxation that both the GPU solver
// (shaders/sphere/) and its CPU reference run: per vertex its one-ring in counter-clockwise order
// with the cotangent weight of each spoke, the vertex's area, and a colouring of the vertices so
// that no two of one colour share an edge. Vertices of one colour move in parallel exactly as
// they would one after another: no energy term and no triangle involves two of them.
#include "gimg/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

struct SphereLevel {
    std::vector<std::uint32_t> ring_offsets;  // V + 1
    // Triangle k of vertex i's fan is (i, ring[o + k], ring[o + (k + 1) % degree]), o = ring_offsets[i].
    std::vector<std::uint32_t> ring;
    std::vector<double> ring_weights;      // (cot alpha + cot beta) / 2 of spoke (i, ring[o + k])
    std::vector<double> vertex_areas;      // a third of the incident triangles' areas
    double total_area = 0.0;
    std::vector<std::uint32_t> colour_offsets;  // colours + 1
    std::vector<std::uint32_t> colour_members;  // vertices, grouped by colour
    std::size_t vertex_count() const { return vertex_areas.size(); }
    std::size_t colour_count() const { return colour_offsets.size() - 1; }
};

// `mesh` must be closed and manifold (check_sphere_input); its positions give the weights.
SphereLevel build_sphere_level(const geo::Mesh& mesh);

// The move of one vertex, identical in shaders/sphere/relax.comp: go towards the minimiser of
// its local energy on the sphere, normalize(sum of w * neighbour) (uniform weights for a Tutte
// step), along the chord, halving the step until no triangle of the fan is flipped that was not
// flipped before. Returns the new position (the old one if no step was allowed).
glm::dvec3 relaxed_position(const SphereLevel& level, const std::vector<glm::dvec3>& y, std::uint32_t vertex,
                            bool uniform_weights);

// One sweep of all colours in order, on the CPU: the reference for the GPU's sweep.
void relax_sweep_cpu(const SphereLevel& level, std::vector<glm::dvec3>& y, bool uniform_weights);

struct LevelStats {
    double energy = 0.0;        // sum over edges of w |y_u - y_v|^2
    std::size_t flips = 0;      // triangles with a . ((b - a) x (c - a)) <= 0
    glm::dvec3 centroid{0.0};   // area-weighted mean of the points
};
LevelStats level_stats_cpu(const SphereLevel& level, const std::vector<glm::dvec3>& y);

// a . ((b - a) x (c - a)): det(a, b, c) with its precision kept on tiny triangles.
double orientation(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

inline constexpr int kMaxStepHalvings = 16;

}  // namespace gimg::passes::detail

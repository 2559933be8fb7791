#pragma once
// One mesh of the sphere hierarchy, laid out for the relaxation that both the GPU solver
// (shaders/sphere/) and its CPU reference run: per vertex its one-ring in counter-clockwise order
// with the cotangent weight of each spoke, and a colouring of the vertices so that no two of one
// colour share an edge. Vertices of one colour move in parallel exactly as
// they would one after another: no energy term and no triangle involves two of them.
#include "gimg/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

struct RelaxationMesh {
    std::vector<std::uint32_t> ring_offsets;  // V + 1
    // Triangle k of vertex i's fan is (i, ring[o + k], ring[o + (k + 1) % degree]), o = ring_offsets[i].
    std::vector<std::uint32_t> ring;
    std::vector<double> ring_weights;           // (cot alpha + cot beta) / 2 of spoke (i, ring[o + k])
    std::vector<std::uint32_t> colour_offsets;  // colours + 1
    std::vector<std::uint32_t> colour_members;  // vertices, grouped by colour
    std::size_t vertex_count() const { return ring_offsets.size() - 1; }
    std::size_t colour_count() const { return colour_offsets.size() - 1; }
};

// `mesh` must be closed and manifold (check_sphere_input); its positions give the weights.
RelaxationMesh build_relaxation_mesh(const geo::Mesh& mesh);

// The move of one vertex, identical in shaders/sphere/relax.comp: go towards the minimiser of
// its local energy on the sphere, normalize(sum of w * neighbour) (uniform weights for a Tutte
// step), along the chord, halving the step until no triangle of the fan gets a worse orientation
// grade (relaxation test passed, only the kernel test of sphere_steps.h passed, neither) and no
// triangle of the lowest grade turns further clockwise. Returns the new position (the old one if
// no step was allowed).
glm::dvec3 relaxed_position(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t vertex,
                            bool uniform_weights);

// One sweep of all colours in order, on the CPU: the reference for the GPU's sweep.
void relax_sweep_cpu(const RelaxationMesh& level, std::vector<glm::dvec3>& y, bool uniform_weights);

struct MapStats {
    double energy = 0.0;              // sum over edges of w |y_u - y_v|^2
    std::size_t flips = 0;            // triangles with det <= 0 (sphere_metrics' flips)
    std::size_t kernel_failures = 0;  // triangles failing the kernel test (flips, and slivers within its margin)
    glm::dvec3 centroid{0.0};         // mean of the points
};
MapStats map_stats_cpu(const RelaxationMesh& level, const std::vector<glm::dvec3>& y);

// Vertices a chunk where the CPU loops over a level on several threads (geo::parallel_for_chunks):
// the chunks, not the threads, fix the order of every sum, so results do not depend on the machine.
inline constexpr std::size_t kLevelChunk = 16384;

inline constexpr int kMaxStepHalvings = 16;

// The relaxation's own kernel test is stricter than the flip test: it keeps every corner of the
// fan above about 1e-6 radians (sin of the angle at the moving vertex). Cotangent weights of
// obtuse triangles are negative, and the local minimiser they give can lie outside the kernel;
// stopping at the kernel's edge with the rounding margin alone left slivers of 1e-9 radians, next
// to which a later vertex split has no room to place its vertex.
inline constexpr double kRelaxMargin = 1e-6;

}  // namespace gimg::passes::detail

#pragma once
// The sphere map of the base mesh that Kanai's hierarchy starts from (the paper uses Alexa's
// method there; its quality matters little, its being one-to-one matters a lot).
//
// Ours: the progressive mesh goes on below the base mesh to a tetrahedron. The tetrahedron is put
// on a regular tetrahedron of the sphere, oriented like the mesh, and its splits are replayed up to
// the base mesh with the same placement and kernel-checked vertex Tutte optimisation as above the
// base (split_refinement.h). At every doubling a few Gauss-Seidel sweeps of the vertex Tutte
// optimisation spread the new vertices out, then the mass centre is moved back to the origin. So
// every step keeps the map one-to-one.
//
// Why only a few sweeps: on the sphere the Tutte energy has no useful minimum. Left to converge it
// draws every point into one spot, or, with the mass centre held at the origin, into two antipodal
// spots, and those near-degenerate maps lose the precision the later splits need (tried: the
// queue optimisation run to its tolerance with uniform weights does exactly that). Gu's Tutte phase
// avoids it the same way, by stopping early.

#include "gimg/geometry/progressive_replay.h"

#include "gimg/geometry/mesh.h"

#include "gimg/passes/sphere.h"

#include <chrono>
#include <string>
#include <vector>

namespace gimg::passes::detail {

inline constexpr std::size_t kBaseMapSweeps = 10;  // per doubling

struct BaseMapRun {
    std::size_t vertex_steps = 0;  // vertex Tutte optimisations applied in the sweeps
    std::size_t placement_failures = 0;
    std::size_t flips = 0;  // at the end (0 unless something failed)
    double energy = 0.0;    // Tutte energy of the base mesh at the end
};

// `replay` must stand at the coarsest mesh; it is advanced to the base mesh, and y (one point per
// vertex of the full mesh) then holds the base mesh's map.
BaseMapRun map_base_mesh(const geo::Mesh& mesh, const geo::ProgressiveMesh& pm, geo::ProgressiveReplay& replay,
                         std::vector<glm::dvec3>& y);

// The start Kanai's method and the harmonic method's fallback share: the progressive mesh down to
// `base_vertices`, the level sizes (`growth` per level), the replay standing at the base mesh and
// the base mesh's map in y; the "progressive mesh" stage (timed from `since`) and the "base map"
// stage are recorded, and a base map that failed somewhere is said in `warnings`.
struct HierarchyStart {
    HierarchyStart(const geo::Mesh& mesh, std::size_t base_vertices, double growth, std::vector<glm::dvec3>& y,
                   std::vector<SphereStage>& stages, std::vector<std::string>& warnings,
                   std::chrono::steady_clock::time_point since);
    HierarchyStart(const HierarchyStart&) = delete;
    HierarchyStart& operator=(const HierarchyStart&) = delete;
    const geo::ProgressiveMesh pm;
    const std::vector<std::size_t> counts;
    geo::ProgressiveReplay replay;  // reads pm
    BaseMapRun base;
};

}  // namespace gimg::passes::detail

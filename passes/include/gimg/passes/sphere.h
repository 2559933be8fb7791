#pragma once
// Conformal spherical parameterization of closed genus-0 meshes (seed 000): every vertex gets a
// point on the unit sphere so that triangles keep their angles and none flips.
//
// Methods: `gu` (Gu et al., the paper's base: Gauss map, Tutte phase, conformal phase, user step
// constants), `kanai` (the paper's method: progressive-mesh hierarchy, vertex splits with local
// Tutte optimisation and the kernel check, priority-queue conformal optimisation per level),
// `linear` (Choi, Lam and Lui 2015: harmonic map to the plane, inverse stereographic projection,
// south-pole Beltrami correction; fast, not guaranteed one-to-one), `gpu` (gimg's: the same
// energies on the same hierarchy as iterative compute dispatches, flip-free parallel updates).

#include "gimg/engine/context.h"
#include "gimg/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace gimg::passes {

// Throws geo::InputError with what is wrong unless the mesh is one closed, manifold, consistently
// oriented piece of genus 0 without degenerate faces: "genus 3: spherical parameterization needs
// genus 0", "2 boundary loops: ...", "non-manifold edge at ...", ...
void check_sphere_input(const geo::Mesh& mesh);

struct AngleStats {
    double mean = 0.0, p95 = 0.0, max = 0.0;  // degrees
};

struct SphereMetrics {
    // Triangles whose three sphere points are not counter-clockwise seen from outside
    // (det(a, b, c) <= 0), degenerate ones included.
    std::size_t flips = 0;
    // F = sum over edges of w_uv |y(u) - y(v)|^2, w_uv = (cot alpha + cot beta) / 2 of the original
    // mesh; tends to 8 pi for a perfectly conformal map onto the unit sphere.
    double conformal_energy = 0.0;
    double conformal_ratio = 0.0;  // conformal_energy / (8 pi)
    // |corner angle on the sphere (spherical triangle of the three points' chords) - on the mesh|.
    AngleStats angle_distortion_deg;
    // Spread of log(area on the sphere / area on the mesh), both normalised to total 1: the
    // standard deviation over triangles, weighted by mesh area.
    double area_distortion = 0.0;
    // The smallest triangle area on the sphere (of the chord triangles; the whole sphere is 4 pi):
    // how far the map shrank the mesh's protrusions.
    double smallest_area = 0.0;
};

// `sphere` holds one unit vector per mesh vertex.
SphereMetrics sphere_metrics(const geo::Mesh& mesh, const std::vector<glm::dvec3>& sphere);

// `mesh` with texture coordinates from the spherical coordinates of its sphere points (+y is the
// pole): u = longitude / 2 pi, v = colatitude / 2 pi, so checker cells are square at the equator.
// Vertices along the seam are duplicated with u + 1 so no triangle wraps around the texture. For
// checker.png, the paper's fig. 1.
geo::Mesh spherical_texture_mesh(const geo::Mesh& mesh, const std::vector<glm::dvec3>& sphere);

// One level or phase of a run: what it did and how long it took.
struct SphereStage {
    std::string name;           // e.g. "tutte", "conformal", "level 3 (1234 vertices)"
    std::size_t vertices = 0;   // active vertices
    std::size_t iterations = 0;
    double seconds = 0.0;
    double energy = 0.0;        // at the end of the stage (the stage's own energy)
};

struct SphereResult {
    std::vector<glm::dvec3> positions;  // one unit vector per mesh vertex
    std::vector<SphereStage> stages;
    bool converged = true;     // false: stopped at an iteration limit, diverged or left a doubt (see note)
    double gpu_ms = 0.0;       // sum of pass timestamps (gpu method with GpuSphereOptions::timestamps)
    std::string note;          // why it did not converge, or anything else worth knowing
};

// Called now and then by long runs (for a terminal progress line).
using SphereProgress = std::function<void(const std::string& stage, std::size_t iteration, double energy,
                                          std::size_t flips, double seconds)>;

struct GuOptions {
    // The paper leaves c_t and c_c to the user; 0.05 is stable on an icosphere (0.5 diverges
    // within a few iterations on the unnormalised Laplacian).
    double tutte_step = 0.05;      // c_t
    double conformal_step = 0.05;  // c_c
    double tolerance = 1e-5;       // stop a phase when |E - E0| < tolerance
    std::size_t max_iterations = 200000;  // per phase
    SphereProgress progress;
};
SphereResult sphere_gu(const geo::Mesh& mesh, const GuOptions& options = {});

struct KanaiOptions {
    std::size_t base_vertices = 300;  // coarsest level of the progressive mesh (100..500 in the paper)
    double growth = 2.0;              // split until the vertex count grows this much, then optimise
    double queue_tolerance = 1e-8;    // stop the priority-queue optimisation below this key
    SphereProgress progress;
};
SphereResult sphere_kanai(const geo::Mesh& mesh, const KanaiOptions& options = {});

SphereResult sphere_linear(const geo::Mesh& mesh);

struct GpuSphereOptions {
    std::size_t base_vertices = 300;          // as KanaiOptions: the same hierarchy
    double growth = 2.0;
    // K: sweeps between read-backs of the energy and recentrings; levels of fewer than 128 K
    // vertices take n / 128 (at least 1), as coarse maps slide towards a point between recentrings.
    std::uint32_t iterations_per_check = 32;
    // A level ends when its energy changed by less than this per sweep over the last K sweeps,
    // relative to it. 3e-6 reaches Gu's energy where Gu finishes (fandisk: 1e-5 stopped at a
    // conformal ratio of 1.00109, Gu's is 1.00078, 3e-6 gives 1.00057) for 8-20% more time (bunny, fandisk, armadillo).
    double tolerance = 3e-6;
    std::size_t max_iterations_per_level = 4000;
    // After the finest level, solve for the map's harmonic shape in a stereographic chart by
    // multigrid-preconditioned conjugate gradients and relax again from there; kept when it flips
    // nothing. It straightens protrusions that the relaxation shrank but left crooked (bunny: mean
    // angle distortion 7.8 degrees without, 0.8 with).
    bool plane_polish = true;
    // With the polish, try the direct route first: the polish applied to Choi, Lam and Lui's
    // pinned-triangle harmonic map (itself solved by the same multigrid conjugate gradients)
    // instead of to the hierarchy's relaxed map, so no progressive mesh is built. Kept when it
    // flips nothing and covers the sphere once; otherwise the hierarchy runs as without it (the
    // note says why). Meshes whose obtuse triangles fold the map beyond repair, or whose
    // protrusions shrink below double precision in the pinned-triangle map, take the hierarchy.
    bool direct = true;
    // With the polish, levels above this many vertices settle to 100x the tolerance in checks of
    // at most 8 sweeps: the polish replaces all but a small cap of the map (bunny, armadillo and
    // armadillo_loop1 end with the same angles to 0.001 degree mean). The finest level settles in
    // full when the polish is not kept. Smaller levels fix the map's global layout and cost little.
    // On the 11 closed genus-0 shared meshes by the hierarchy alone, 2,000 instead of 10,000 gave
    // the same mean angles to 0.11 degrees on 9, better on cow (9.93 -> 9.87) and on camel, whose
    // polish then holds (36.4 -> 12.8 degrees mean), in 1.1-2.3x less time; 500 lost up to 0.5
    // degrees on cow, triceratops and dino.
    std::size_t loose_levels_above = 2000;
    // GPU time of every pass from timestamps, summed in SphereResult::gpu_ms. Off by default: on
    // lavapipe each timestamped pass costs about 0.2 ms (a third of the whole run on fandisk) and
    // its timestamps do not cover compute work anyway.
    bool timestamps = false;
    SphereProgress progress;
};
SphereResult sphere_gpu(Context& ctx, const geo::Mesh& mesh, const GpuSphereOptions& options = {});

}  // namespace gimg::passes

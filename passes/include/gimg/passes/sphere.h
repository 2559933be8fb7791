#pragma once
// Conformal spherical parameterization of closed genus-0 meshes (Kanai, "Robust and fast
// calculation of conformal spherical parameterization", 2005; docs/sphere.md): every vertex gets a
// point on the unit sphere so that triangles keep their angles and none flips.
//
// Methods: `harmonic` (gimg's default, on the render graph: the harmonic map of the mesh in a
// stereographic chart of the sphere, solved by multigrid conjugate gradients and relaxed on the
// sphere, flip-free), `kanai` (progressive-mesh hierarchy, vertex splits with local Tutte
// optimisation and the kernel check, priority-queue conformal optimisation per level), `gu` (Gu et
// al. 2004: Gauss map, Tutte phase, conformal phase, user step constants), `linear` (Choi, Lam and
// Lui 2015: harmonic map to the plane, inverse stereographic projection, south-pole Beltrami
// correction; fast, not guaranteed one-to-one).

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
    std::string name;          // e.g. "tutte", "conformal", "level 3 (1234 vertices)"
    std::size_t vertices = 0;  // active vertices
    std::size_t iterations = 0;
    double seconds = 0.0;
    double energy = 0.0;  // at the end of the stage (the stage's own energy)
};

struct SphereResult {
    std::vector<glm::dvec3> positions;  // one unit vector per mesh vertex
    std::vector<SphereStage> stages;
    bool converged = true;  // false: stopped at an iteration limit, diverged or left a doubt (see note)
    double gpu_ms = 0.0;    // sum of pass timestamps (harmonic method with HarmonicSphereOptions::timestamps)
    std::string note;       // why it did not converge, or anything else worth knowing
};

// Called now and then by long runs (for a terminal progress line).
using SphereProgress = std::function<void(const std::string& stage, std::size_t iteration, double energy,
                                          std::size_t flips, double seconds)>;

struct GuOptions {
    // The paper leaves c_t and c_c to the user; 0.05 is stable on an icosphere (0.5 diverges
    // within a few iterations on the unnormalised Laplacian).
    double tutte_step = 0.05;             // c_t
    double conformal_step = 0.05;         // c_c
    double tolerance = 1e-5;              // stop a phase when |E - E0| < tolerance
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

struct HarmonicSphereOptions {
    // The progressive-mesh hierarchy, used when the pinned-triangle start folds beyond repair or
    // with direct = false: as KanaiOptions.
    std::size_t base_vertices = 300;
    double growth = 2.0;
    // K: relaxation sweeps between read-backs of the energy and recentrings; levels of fewer than
    // 128 K vertices take n / 128 (at least 1), as coarse maps slide towards a point between
    // recentrings.
    std::uint32_t iterations_per_check = 32;
    // A level's relaxation ends when its energy changed by less than this per sweep over the last K
    // sweeps, relative to it.
    double tolerance = 3e-6;
    std::size_t max_iterations_per_level = 4000;
    // After the relaxation, solve for the map's harmonic shape in a stereographic chart (a pinned
    // cap around the pole, multigrid-preconditioned conjugate gradients) and relax again from
    // there; kept when it flips nothing. It straightens protrusions that the relaxation shrank
    // but left crooked.
    bool plane_polish = true;
    // With plane_polish: start from Choi, Lam and Lui's pinned-triangle harmonic map (solved by
    // the same conjugate gradients) instead of the hierarchy's relaxed map, so no progressive mesh
    // is built. Kept when it flips nothing and covers the sphere once; otherwise the hierarchy
    // runs (the result's note says why).
    bool direct = true;
    // With plane_polish, hierarchy levels above this many vertices are relaxed only to 100x the
    // tolerance, in checks of at most 8 sweeps: the chart solve replaces all but its pinned cap.
    // The finest level is relaxed in full when the chart solve is rejected.
    std::size_t loose_levels_above = 2000;
    // GPU time of every pass from timestamps, summed in SphereResult::gpu_ms (costly on lavapipe).
    bool timestamps = false;
    SphereProgress progress;
};
SphereResult sphere_harmonic(Context& ctx, const geo::Mesh& mesh, const HarmonicSphereOptions& options = {});

}  // namespace gimg::passes

#pragma once
// PolyCubes and polycube maps for closed and open meshes (Satoh & Imai, after He, Wang, Fu &
// Qin 2009; docs/polycube.md). Every hole of the mesh is capped by a temporary fan, so the whole
// construction runs on a closed surface whose cap triangles are remembered:
//  1. critical structure: a harmonic function, 0 at the lowest and 1 at the highest vertex, and
//     its saddles by sign changes around each link;
//  2. horizontal cutting planes halfway between the sorted critical heights, refined to at most
//     d_z apart; every plane's section of the mesh, whose runs through cap triangles (the paper's
//     gaps between chains) are closed in the plane by the paper's cubic Bezier or its fallback
//     polyline; per plane a rectilinear region from a quadtree refined until
//     (area(p) - area(c)) / area(c) < d_a; the layers stacked into a closed orthogonal polyhedron;
//  3. the map: every slab piece of the mesh and its polycube piece cut to disks along matching
//     paths and each mapped onto the unit disk by a Tutte map (positive weights, solved by the
//     solver module), the boundary matched by arc length; the composition is the map, the same on
//     a contour from above and below. The images of cap triangles are the polycube's hole regions;
//  4. chart smoothing: sweeps moving every vertex's image to the harmonic mean of its neighbours'
//     and back onto the polycube, kept where no triangle around it turns away from the faces.

#include "gimg/engine/context.h"
#include "gimg/geometry/mesh.h"

#include <glm/vec2.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace gimg::passes {

struct PolycubeOptions {
    double dz = 0.0;   // largest gap between cutting planes; 0: bounding-box height / 20
    double da = 0.05;  // quadtree stop: (area(p) - area(c)) / area(c) < da
    // Deepest quadtree level. Every quadtree is rooted at the model's bounding rectangle (the
    // layers must line up), not at its contour's.
    std::uint32_t max_level = 8;
    std::uint32_t k = 2;             // parts per half of the fallback closing polyline
    std::uint32_t max_repairs = 96;  // planes the connectivity check may insert
    // Sweeps of umbrella smoothing (each vertex halfway to its neighbours' mean) of the copy of the
    // surface that the planes cut and the layers follow; 0: the mesh itself. Same vertices and
    // faces, so the map is still the mesh's; the distortion is measured on the mesh's positions.
    std::uint32_t slice_smoothing = 0;
    // When the construction fails along an axis, it is built again with slice_smoothing at least 3
    // (the pits of a scanned surface), then with the quadtree down to level 10 (thin handles,
    // contours closer than a cell), then with both, before the next axis.
    bool retry = true;
    // No further attempt (retry or axis) starts once the attempts so far took longer than this, and
    // one still running then stops at its next round of the connectivity check or before its map,
    // so that a mesh every attempt fails on fails in about this time (the first attempt is never
    // stopped).
    double retry_seconds = 60.0;
    bool map = true;               // also build the map (step 3)
    std::uint32_t smoothing = 10;  // sweeps of chart smoothing over the map (step 5); 0: none
    // The planes' normal: 0 x, 1 y, 2 z (the paper's); 3 auto: z, then y, then x while the
    // polycube or the map fails.
    std::uint8_t axis = 3;
};

// ---- Step 1: holes capped, critical structure ----

// The mesh with every boundary loop closed by a fan around a new vertex at the loop's centroid:
// vertices from `original_vertices` on are the fan centres, faces from `original_faces` on the caps.
struct CappedMesh {
    geo::Mesh mesh;
    std::size_t original_vertices = 0, original_faces = 0, loops = 0;
};
// Throws geo::InputError unless the mesh is a manifold, oriented surface of one piece.
CappedMesh cap_holes(const geo::Mesh& mesh);

struct CriticalStructure {
    std::vector<double> f;                    // harmonic, per vertex, 0 at `minimum`, 1 at `maximum`
    std::uint32_t minimum = 0, maximum = 0;   // lowest and highest vertex in z (ties by index)
    std::vector<std::uint32_t> saddles;       // saddle vertices
    std::vector<std::uint32_t> multiplicity;  // per saddle: (sign changes - 2) / 2
    std::size_t extrema = 0;                  // vertices with no sign change (2 for a good f)
    std::size_t saddle_count() const;         // with multiplicity: 2 g on a closed surface
    std::size_t iterations = 0;
    bool converged = false;
};
// On a closed mesh; ctx null: the CPU twin of the solve.
CriticalStructure critical_structure(Context* ctx, const geo::Mesh& closed_mesh);

// ---- Step 2-1: cutting planes ----

struct CuttingPlane {
    double z = 0.0;
    bool inserted = false;  // false: halfway between two critical heights; true: added by d_z or a repair
};
// `critical_z`: the heights of the minimum, the saddles and the maximum, any order. Heights closer
// than `merge` merge into one; 2g + 1 midpoint planes, then floor(gap / dz) evenly spaced planes
// in every gap wider than dz, the two end gaps (minimum to first plane, last plane to maximum) too.
std::vector<CuttingPlane> cutting_planes(std::vector<double> critical_z, double dz, double merge);

// ---- Closing a gap in a plane (sec. 3.1-3.2) ----

// The half-line from `from` along `direction` (any length, not zero) and the one from `to` along
// `to_direction` meet at the returned point, or they do not (parallel, or behind either start).
std::optional<glm::dvec2> ray_intersection(glm::dvec2 from, glm::dvec2 direction, glm::dvec2 to,
                                           glm::dvec2 to_direction);
// The cubic Bezier r0, m0, m1, r1 with m_i halfway between r_i and the rays' meeting point,
// sampled at `segments` + 1 points (r0 first, r1 last); empty when the rays do not meet.
std::vector<glm::dvec2> bezier_closure(glm::dvec2 r0, glm::dvec2 d0, glm::dvec2 r1, glm::dvec2 d1,
                                       std::uint32_t segments);
// The fallback polyline: r0, c_01..c_0k, c_1k..c_11, r1 (2k + 2 points), c_ij on the perpendicular
// from q_ij = r_i + j/k (m_r - r_i) to ray i, at j/(k+1) of the way from the ray.
std::vector<glm::dvec2> fallback_closure(glm::dvec2 r0, glm::dvec2 d0, glm::dvec2 r1, glm::dvec2 d1, std::uint32_t k);

// ---- Step 2-2: rectilinear region by a quadtree ----

struct Rect {
    glm::dvec2 min{0.0}, max{0.0};
};
// The union of the cells of a quadtree over `root` that meet the even-odd region of `loops`; every
// cell subdivided to `depth`, so `cells` is a (2^depth)^2 bitmap, row after row from root.min.
struct RectilinearRegion {
    Rect root;
    std::uint32_t depth = 0;
    std::vector<std::uint8_t> cells;
    double region_area = 0.0;  // area(c)
    double area = 0.0;         // area(p)
    double excess() const { return region_area > 0.0 ? (area - region_area) / region_area : 0.0; }
    bool topology_ok = false;         // components, holes and touching as the loops' region
    std::size_t carved = 0;           // cells given up where components came closer than a cell (0: p holds c)
    std::vector<std::int32_t> owner;  // per cell: the component (outer loop and its holes), -1 empty
    std::vector<std::int32_t> component_of_loop;  // per loop: its component (-1: fewer than 3 points)
    std::vector<std::uint32_t> component_depth;   // per component: the depth it was refined to
};
// Refines from depth min_depth until excess() < da and the topology matches with nothing carved (or
// max_level). Pockets a component's cells enclose that hold none of its holes are filled.
RectilinearRegion rectilinear_region(const std::vector<std::vector<glm::dvec2>>& loops, Rect root, double da,
                                     std::uint32_t max_level, std::uint32_t min_depth = 0);

// ---- The whole construction ----

enum class Closure { Bezier, Fallback, Chord, Failed };

struct PolycubeStatistics {
    std::size_t genus = 0, holes = 0, saddles = 0, extrema = 0;
    std::uint8_t axis = 2;                             // the planes' normal used (0 x, 1 y, 2 z)
    std::size_t axes_tried = 1;                        // with axis auto: how many axes were built
    std::size_t attempts = 1;                          // constructions run, every axis and retry
    bool retries_cut_short = false;                    // attempts left untried or stopped: retry_seconds had passed
    std::uint32_t max_level = 8, slice_smoothing = 0;  // the options of the attempt returned
    std::size_t planes = 0, inserted_planes = 0, repair_planes = 0, moved_planes = 0;
    std::string repair_note;  // why the first planes were inserted (the first few mismatches)
    std::size_t contours = 0, chains = 0, closed_by_bezier = 0, closed_by_fallback = 0, closed_by_chord = 0,
                closing_failed = 0;
    std::uint32_t quadtree_depth = 0;  // deepest plane
    double mean_excess = 0.0;          // of (area(p) - area(c)) / area(c) over the planes' regions
    std::size_t cells_filled = 0;      // cells added so the polyhedron is manifold
    std::size_t cells_carved = 0;      // cells given up where neighbouring layers' unjoined pieces touched
    std::size_t cells_opened = 0;      // cells opened as passages for air the layers enclosed
    std::size_t polycube_faces = 0, polycube_corners = 0, polycube_triangles = 0;
    long long euler_characteristic = 0;
    bool polycube_valid = false;  // closed, manifold, one piece, axis-aligned, chi = 2 - 2g
    std::string invalid_reason;
    // The map
    bool mapped = false;
    std::string map_note;
    std::size_t pieces = 0, pieces_mapped = 0, hole_triangles = 0, cut_mismatch = 0;
    std::size_t holes_marked = 0;  // holes of the mesh with a region on the polycube (all of them, for a map)
    // Triangles turned over in the map: the map is the mesh side's disk map followed by the
    // inverse of the polycube side's, so it is one-to-one exactly when both are embeddings.
    std::size_t flips = 0;
    // Mesh triangles whose straight image (mapped.ply: the vertices moved, the faces kept) faces
    // away from the polycube faces under its corners: where a triangle spans several polycube
    // faces (stairs finer than the mesh), its chord through them need not face outwards.
    std::size_t turned_chords = 0;
    // Largest move of a contour vertex from where the disks put it (the circle's chords) to its
    // matched point on the polycube loop, over the diagonal.
    double boundary_snap = 0.0;
    double area_distortion = 0.0, angle_distortion = 0.0;                // area-weighted means, 1 ideal
    double area_distortion_median = 0.0, angle_distortion_median = 0.0;  // area-weighted medians
    // Before the chart smoothing (step 5): the means, medians and turned chords; the moves it kept
    // (each moving an image).
    double area_distortion_unsmoothed = 0.0, angle_distortion_unsmoothed = 0.0;
    double area_distortion_median_unsmoothed = 0.0, angle_distortion_median_unsmoothed = 0.0;
    std::size_t turned_chords_unsmoothed = 0, smoothing_moves = 0;
    double solve_seconds = 0.0, seconds = 0.0;  // of every attempt
    std::size_t solves = 0, solve_iterations = 0;
};

struct Polycube {
    geo::Mesh surface;                    // closed, triangulated; every normal one of +-x, +-y, +-z
    std::vector<std::uint8_t> hole;       // per surface triangle: 1 in a hole region of the mesh
    std::vector<std::uint8_t> face_axis;  // per surface triangle: 0..5 = +x, -x, +y, -y, +z, -z
    std::vector<CuttingPlane> planes;
    // Per plane, per contour: the closed loop, in the plane's own coordinates (x, y for axis z,
    // y, z for axis x, z, x for axis y).
    std::vector<std::vector<std::vector<glm::dvec2>>> closed_contours;
    std::vector<glm::dvec3> mapped;  // per input vertex: its image on the surface (empty without the map)
    PolycubeStatistics stats;
};

// Why an attempt failed: its invalid_reason or map_note in a sentence (empty when it did not fail).
std::string failure_of(const PolycubeStatistics& stats, bool map);

// ctx null: every solve by its CPU twin. Throws geo::InputError for a mesh it cannot take.
// `retrying`, when given, hears of every failed attempt that another one follows (its statistics:
// axis, attempts, max_level, slice_smoothing and why), so a caller can say what is going on.
Polycube build_polycube(Context* ctx, const geo::Mesh& mesh, const PolycubeOptions& options = {},
                        const std::function<void(const PolycubeStatistics& failed)>& retrying = {});

// The six axes as the index face_axis uses, for a unit normal (the largest |component|).
std::uint8_t axis_of(const glm::dvec3& normal);

}  // namespace gimg::passes

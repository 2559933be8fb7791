#pragma once
// Pieces of the polycube construction shared by its files (not a public interface).

#include "gimg/geometry/adjacency.h"
#include "gimg/passes/polycube.h"
#include "gimg/passes/solvers.h"

#include <glm/vec2.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace gimg::passes::polycube {

// Per edge of `adj`, the cotangent weight clamped to max(w, 1e-3 mean |w|) > 0: positive weights
// keep the discrete maximum principle (no spurious extrema, Tutte maps one-to-one).
std::vector<double> positive_cotangent_weights(const geo::Mesh& mesh, const geo::MeshAdjacency& adj);

// The Laplacian with positive_cotangent_weights. Rows with fixed[i] are Dirichlet
// rows holding fixed_values (rhs_count per row).
LinearSystem positive_laplacian(const geo::Mesh& mesh, const geo::MeshAdjacency& adj,
                                const std::vector<std::uint8_t>& fixed, const std::vector<double>& fixed_values,
                                std::uint32_t rhs_count);

// One solve on the GPU when ctx is given, by its CPU twin otherwise; adds to the statistics.
SolveResult solve(Context* ctx, const LinearSystem& system, PolycubeStatistics& stats);

// Boundary loops of a triangle set, each in the faces' direction (interior on the left), each
// from its smallest vertex, in the order of those. Throws geo::InputError when a vertex has more
// than one outgoing boundary edge. Its arrays are as long as the largest vertex index.
std::vector<std::vector<std::uint32_t>> boundary_loops(const std::vector<glm::uvec3>& triangles);

// An undirected edge as one sortable number (lower end in the high half).
inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

// Pieces of a triangle set: triangles sharing an edge are joined where same(f, g) says so (f the
// edge's first triangle, g a later one). Returns each triangle's piece as the piece's root
// triangle, so two triangles are in one piece when their roots are equal.
std::vector<std::uint32_t> join_across_edges(const std::vector<glm::uvec3>& triangles,
                                             const std::function<bool(std::uint32_t, std::uint32_t)>& same);

// The mesh cut by horizontal planes: every edge crossing a plane split there (the new vertex
// exactly at the plane's z), every crossed triangle split in three. Vertices keep their ids;
// new ones follow.
struct SlicedMesh {
    geo::Mesh mesh;
    std::vector<std::uint32_t> source_face;  // per triangle: the face of the input it lies in
    std::vector<std::int32_t> plane_of;      // per vertex: the plane it lies on, -1 for none
};
// `carried`: per vertex of `mesh`, a position of its own (the mesh's true one where the planes cut
// a smoothed copy); each new vertex gets it interpolated as the cut does.
SlicedMesh slice_mesh(const geo::Mesh& mesh, const std::vector<double>& plane_z,
                      std::vector<glm::dvec3>* carried = nullptr);

// One contour of a plane: a closed loop of sliced-mesh vertices, and per segment (vertices[i] to
// vertices[i + 1]) whether it crosses a cap triangle (the paper's gap between chains).
struct Contour {
    std::uint32_t plane = 0;
    std::vector<std::uint32_t> vertices;
    std::vector<std::uint8_t> gap;
    std::vector<glm::dvec2> closed;  // the loop in the plane with every gap closed (sec. 3.1-3.2)
};
std::vector<Contour> plane_contours(const SlicedMesh& sliced, std::size_t plane_count, std::size_t original_faces);

struct ClosureCounts {
    std::size_t chains = 0, bezier = 0, fallback = 0, chord = 0, failed = 0;
};
// Fills every contour's `closed`: real segments as they are, each run of gap segments replaced by
// the Bezier closure, else the fallback, else the chord (whichever first crosses no real segment of
// the plane), else left as the cap's section.
ClosureCounts close_contours(const geo::Mesh& sliced, std::vector<Contour>& contours, std::uint32_t k,
                             double sample_length);

// 2D helpers.
double signed_area(const std::vector<glm::dvec2>& loop);
double distance_to_loop(glm::dvec2 p, const std::vector<glm::dvec2>& loop);            // to the closed polyline
bool point_in_loops(const std::vector<std::vector<glm::dvec2>>& loops, glm::dvec2 p);  // even-odd
bool segments_cross(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d);           // proper or touching

}  // namespace gimg::passes::polycube

namespace gimg::passes::polycube {

// Step 2-3: the layers stacked. Layer i is plane i's bitmap (all at one depth over one root)
// extruded from halfway to the plane below (the mesh's lowest z for the first) to halfway to the
// plane above (the highest z for the last).
struct Layers {
    Rect root;
    std::uint32_t depth = 0;
    std::vector<std::vector<std::uint8_t>> cells;  // per plane, (2^depth)^2
    std::vector<std::vector<std::int32_t>> owner;  // per plane, per cell: its component (-1 empty)
    std::vector<std::set<std::pair<std::int32_t, std::int32_t>>> joins;  // per plane p: the components of
                                                                         // p and p + 1 a mesh piece joins
    std::vector<double> plane_z;
    double bottom = 0.0, top = 0.0;
    std::size_t opened = 0;  // cells opened as passages for enclosed air (open_air_passages)
};
// Per slab (slab s between planes s - 1 and s), the pairs (contour on plane s - 1, contour on plane
// s) that one piece of the mesh between the two planes joins.
using JoinedContours = std::vector<std::set<std::pair<std::int32_t, std::int32_t>>>;

// Step 2-2 for every plane: the rectilinear regions of its closed contours over one root (the
// bounding rectangle of the model and of every closed contour), all at the deepest plane's depth;
// `excess` gets the sum of the planes' (area(p) - area(c)) / area(c). Components of neighbouring
// layers that overlap or touch where no mesh piece joins them are refined further, and at
// max_level the farther cell of each such touch is given up (`carved` counts them).
Layers stacked_regions(const std::vector<Contour>& contours, const std::vector<double>& plane_z, const geo::Bounds& box,
                       double da, std::uint32_t max_level, const JoinedContours& joined, double& excess,
                       std::size_t& carved);

// Opens a corridor in the next layer for the air of every hole whose contour a mesh piece joins to
// a contour of that layer's plane while the layers keep the air enclosed (`component`: per contour,
// its component on its plane); returns the cells opened.
std::size_t open_air_passages(std::vector<std::vector<std::int32_t>>& owner, int n, const Rect& root,
                              const std::vector<Contour>& contours, const std::vector<std::int32_t>& component,
                              const JoinedContours& joined);

// Loops of the section of `mesh` by the plane at height h.
std::size_t section_loops(const geo::Mesh& mesh, double h);
// Heights in (lo, hi) for a plane, best first: the fewest loops in the section, then nearest
// `prefer` (itself a candidate when inside).
std::vector<double> quiet_heights(const geo::Mesh& mesh, double lo, double hi, double prefer);
// The height in (lo, hi) for a repair plane: the section with the fewest loops in the middle half of
// the slab, nearest its middle; with `handle` (a slab piece of `sliced` that is not of genus 0)
// the first such height anywhere in the slab that leaves every piece of `handle` of genus 0.
double repair_height(const geo::Mesh& mesh, const SlicedMesh& sliced, const std::vector<std::uint32_t>* handle,
                     double lo, double hi);

// Fills cells until every edge and corner of the stack is manifold, never one that would join two
// pieces of a layer or touch a component of a neighbouring layer the mesh does not join to its
// own; returns how many cells it filled or gave up.
std::size_t make_manifold(Layers& layers);

struct PolycubeSurface {
    geo::Mesh mesh;
    std::vector<std::uint8_t> axis;   // per triangle, as axis_of
    std::vector<std::uint32_t> slab;  // per triangle: 0 below plane 0, i + 1 above plane i
    std::vector<std::vector<std::vector<std::uint32_t>>>
        loops;  // per plane: its walls' loops at the plane, ccw from above
    std::size_t faces = 0, corners = 0;
};
PolycubeSurface polycube_surface(const Layers& layers);

}  // namespace gimg::passes::polycube

namespace gimg::passes::polycube {

// Step 3: the map. `hole_of_face`: per face of the capped mesh, the hole its cap closes (-1: none).
// `loop_contour[p][l]`: the contour (index into `contours`) that loop l of the
// surface at plane p stands for. `piece_pairs`: per slab piece, its triangles in the sliced mesh
// and in the surface.
struct PiecePair {
    std::vector<std::uint32_t> mesh_triangles, surface_triangles;
};
struct PolycubeMap {
    std::vector<glm::dvec3> image;           // per sliced-mesh vertex
    std::vector<std::uint8_t> image_axis;    // per sliced-mesh vertex: the axis of the face it landed on
    std::vector<std::uint8_t> surface_hole;  // per surface triangle
    std::size_t pieces_mapped = 0, cut_mismatch = 0, holes_marked = 0;
    std::size_t disk_flips = 0;  // triangles of either disk map turned over (0 for embeddings)
    double boundary_snap = 0.0;  // largest move of a contour vertex from its located image to its matched point
    std::string note;
};
PolycubeMap map_pieces(Context* ctx, const SlicedMesh& sliced, const std::vector<Contour>& contours,
                       const PolycubeSurface& surface, const std::vector<std::vector<std::int32_t>>& loop_contour,
                       const std::vector<PiecePair>& pieces, const std::vector<std::int32_t>& hole_of_face,
                       PolycubeStatistics& stats);

}  // namespace gimg::passes::polycube

namespace gimg::passes::polycube {

// Pieces of one slab each joined across edges: their triangles, slab, the contours they touch and
// whether each is of genus 0 (chi = 2 - loops).
struct SlabPieces {
    std::vector<std::vector<std::uint32_t>> triangles;
    std::vector<std::uint32_t> slab;
    std::vector<std::set<std::int32_t>> contours;
    std::vector<bool> disk_like;
};
// The sliced mesh's slab pieces (slab 0 below plane 0, i + 1 above plane i), once per round for
// joined_contours and check_slabs.
SlabPieces mesh_slab_pieces(const SlicedMesh& sliced, const std::vector<Contour>& contours,
                            const std::vector<double>& plane_z);

JoinedContours joined_contours(const SlabPieces& mesh_pieces, const std::vector<Contour>& contours,
                               const std::vector<double>& plane_z);

// Per plane, per loop of the walls at that plane: the contour it stands for (the nearest, one to
// one; -1 when the plane has more loops than contours).
std::vector<std::vector<std::int32_t>> match_loops(const PolycubeSurface& surface, const std::vector<Contour>& contours,
                                                   std::size_t plane_count);

// Every slab piece of the mesh (between consecutive planes) against the polycube's: pieces of
// genus 0 that join the same contours pair up; `bad_slabs` and `bad_planes` (whose loops and
// contours differ in number) are where they do not, `reasons` says how.
struct SlabCheck {
    std::vector<PiecePair> pairs;
    std::set<std::uint32_t> bad_slabs;
    std::vector<std::size_t> bad_planes;
    std::vector<std::string> reasons;
    std::size_t mesh_pieces = 0;
};
SlabCheck check_slabs(const SlabPieces& mesh_pieces, const std::vector<Contour>& contours,
                      const PolycubeSurface& surface, const std::vector<std::vector<std::int32_t>>& loop_contour,
                      const std::vector<double>& plane_z);

// Step 5: `iterations` sweeps of chart smoothing over every vertex's image (and the axis of the
// polycube face it lies on); returns the moves kept. `rest`: the mesh's own positions, against
// which the distortion is measured; triangles whose source face is `original_faces` or more (the
// holes' caps) are left out of it.
std::size_t smooth_map(const SlicedMesh& sliced, const std::vector<glm::dvec3>& rest, std::size_t original_faces,
                       const geo::Mesh& surface, const std::vector<std::uint8_t>& surface_axis,
                       std::vector<glm::dvec3>& image, std::vector<std::uint8_t>& image_axis, std::uint32_t iterations);

// A triangle of the mesh whose image faces away from the polycube faces under its corners (per
// vertex, the axis index of its face), or whose image's squared doubled area is at most min_area2.
bool turned(const glm::uvec3& t, const std::vector<glm::dvec3>& image, const std::vector<std::uint8_t>& axis,
            double min_area2 = 0.0);

// The area and the angle distortion of the map from triangle a to triangle b (each 1 for a
// similarity of the right scale); infinite where b is collapsed.
std::pair<double, double> triangle_distortion(const glm::dvec3 a[3], const glm::dvec3 b[3]);

// The factor that gives the image the area of `rest` over the real triangles (source face below
// original_faces), at which the distortion is measured.
double image_scale(const SlicedMesh& sliced, const std::vector<glm::dvec3>& rest, const std::vector<glm::dvec3>& image,
                   std::size_t original_faces);

// turned_chords, and the distortion means and medians over the real triangles of the cut mesh.
void measure_map(const SlicedMesh& sliced, const PolycubeMap& map, std::size_t original_faces,
                 PolycubeStatistics& stats);

}  // namespace gimg::passes::polycube

#pragma once
// Parameterization geometry images (the cylindrical-projection thesis, chapter 6; docs/gim.md): a
// disk-like mesh is mapped onto the unit square by a weighted Tutte system with its boundary fixed,
// the weights are reweighted iteratively to even out the sampling density (and to concentrate it at
// curvature), and the map is sampled on an N x N grid whose border lies on the boundary.
//
// Variants (the reweighting each iteration applies to w_ij before the rows are normalised):
//   tutte      w_ij = 1, no iteration
//   floater    Floater's shape-preserving weights (1997), no iteration; every variant starts here
//   stretch    Yoshizawa, Belyaev & Seidel (SMI 2004): w_ij /= sigma(v_j), the vertex L2 stretch
//   density    w_ij *= sqrt((A_i + A_j) / (2 A_i)), A the 2D one-ring areas (eq. 6.8), corners x4
//              and boundary x2 (6.9)
//   uniform3d  the same with A_i / A_i,3D (6.10)
//   curvature  the same with A_i / A_i,3D / C_i, C the bilaterally smoothed (k1^2 + k2^2)^(1/N) (6.15)

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/bvh.h"
#include "gimg/geometry/disk_cut.h"
#include "gimg/geometry/mesh.h"
#include "gimg/passes/reconstruct.h"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace gimg::passes {

// The boundary loop of a disk mesh placed on the unit square: corners at (0,0), (1,0), (1,1),
// (0,1) in that order, the interior on the left (counter-clockwise), the vertices between two
// corners spaced by chord length.
struct SquareBoundary {
    std::vector<std::uint32_t> loop;         // boundary vertices in order, starting at corners[0]
    std::array<std::uint32_t, 4> corners{};  // vertex indices
    std::vector<glm::dvec2> uv;              // one per loop entry
};

// Throws geo::InputError with the reason unless the mesh is one component, manifold, oriented and
// has exactly one boundary loop of at least 4 vertices (and no vertex outside its faces).
void check_disk_mesh(const geo::Mesh& mesh);
// Corners: the given boundary vertices (in boundary order), or four a quarter of the perimeter
// apart where the boundary turns the most, each moved to the nearest apex of an ear (a face of
// three consecutive boundary vertices, which would lie flat on a side) within a 32nd of the
// perimeter; corner 0 is the one with the smallest index (docs/gim.md). Throws geo::InputError
// when a given corner is not on the boundary or the four are not distinct and in order.
SquareBoundary square_boundary(const geo::Mesh& mesh, const geo::MeshAdjacency& adjacency,
                               const std::optional<std::array<std::uint32_t, 4>>& corners = std::nullopt);

// Floater's shape-preserving weights (1997): per interior vertex, the mean over its neighbours of
// the barycentric coordinates of the vertex in the triangle of its geodesic polar map hit by the
// ray opposite that neighbour. slot_weights[k] belongs to adjacency.vertex_vertices[k]; rows of
// interior vertices are positive and sum to 1; boundary rows are 0. A vertex whose flattened star
// has a scaled angle of pi or more (no containing triangle for some neighbour) gets chord-length
// weights instead, counted in `fallbacks`.
std::vector<double> floater_weights(const geo::Mesh& mesh, const geo::MeshAdjacency& adjacency,
                                    std::size_t* fallbacks = nullptr);
// The same for the rows marked in `interior` (1: an interior vertex), for a caller that knows them
// (adjacency.interior_vertices() walks every vertex's fan).
std::vector<double> floater_weights(const geo::Mesh& mesh, const geo::MeshAdjacency& adjacency,
                                    const std::vector<std::uint8_t>& interior, std::size_t* fallbacks = nullptr);

// Throws geo::InputError with the reason unless the mesh is one component, manifold and oriented
// (any genus, any number of boundary loops), as cut_to_disk needs.
void check_cuttable_mesh(const geo::Mesh& mesh);

// A surface cut open into a disk for the square map (Gu, Gortler and Hoppe, "Geometry images",
// SIGGRAPH 2002, sec. 3; geo::initial_cut and docs/gim.md): an initial cut graph, or on a closed
// genus-0 surface a seam between two far vertices, moved off the strips it closes in
// (geo::zip_closed_in), then `max_paths` paths, each from the vertex of largest L2 stretch in
// Floater's map of the surface opened so far to the cut. Of the cuts with the first k paths the one
// kept has the fewest turned triangles in its map, then the least L2 stretch; a path must lower it by
// `stop_fall` to count. Where the two initial cut graphs differ (higher genus, several holes), both
// are tried so, unless `graph` names one, and of their two cuts the one kept again turns fewer
// triangles, then has the lower L2 stretch.
struct DiskCutOptions {
    std::size_t max_paths = 8;
    double stop_fall = 0.01;
    std::optional<geo::CutGraph> graph;
};
struct DiskCut {
    geo::Mesh disk;  // the mesh opened along the cut: one boundary loop
    // disk vertex -> the mesh's vertex it copies; kInvalidIndex for a vertex added at the midpoint of
    // an edge joining two boundary vertices (geo::split_dividing_edges)
    std::vector<std::uint32_t> source;
    std::size_t split_edges = 0;
    std::size_t cut_edges = 0;  // the mesh's edges on the cut (each two boundary edges of the disk)
    double cut_length = 0.0;    // their summed length
    std::size_t paths = 0;      // stretch paths kept: the first `paths` of those tried
    // Per input vertex, its cut edges plus its boundary edges: 2 along a cut path or a hole's rim,
    // 1 at a path's end, 3 or more where paths meet.
    std::vector<std::uint32_t> cut_degree;
    // Floater's map's L2 stretch: of the initial cut, then with each path tried (infinite where a
    // triangle turned over)
    std::vector<double> l2_stretch;
    geo::CutGraph graph = geo::CutGraph::FaceTree;  // the initial cut graph kept
    std::size_t tried = 0;                          // cuts mapped, of both initial graphs
    // Where both initial graphs were tried: the L2 stretch of each one's cut (FaceTree,
    // ShortestLoops; infinite where it turns triangles over)
    std::vector<double> graph_l2_stretch;
};
// Floater's maps on the GPU, or with ctx == nullptr the CPU twin. Throws geo::InputError for a mesh
// check_cuttable_mesh refuses.
DiskCut cut_to_disk(Context* ctx, const geo::Mesh& mesh, const DiskCutOptions& options = {});

// The square's boundary for a cut surface that samples both sides of every cut path alike, so
// that the image's border pixels come in pairs holding the same point and the reconstruction closes
// over the seam (Gu, Gortler and Hoppe 2002, sec. 4): the boundary loop's nodes (copies of vertices
// where paths end or meet, and where they meet a hole) go to whole pixel steps of the square's
// perimeter, both sides of a path get the same number of steps in proportion to its length, the
// vertices between by chord length; a vertex is added where a corner of the square falls inside a
// boundary edge (cut.disk and cut.source grow). `mate` has a perimeter step per border pixel,
// counter-clockwise from (0, 0), 4 (size - 1) in all: the step of the pixel sampling the same point
// (itself on a hole's rim). A loop from a node back to itself (a hole's rim, a small handle) gets at
// least 5 steps and each of two paths between the same two nodes 3, or joined they would pinch.
// std::nullopt where the loop has no node (nothing to join), for a size under 4 (joined, no face
// would be left) or where the perimeter has too few steps at this size for those minimums.
struct SeamBoundary {
    SquareBoundary boundary;
    std::vector<std::uint32_t> mate;
};
std::optional<SeamBoundary> seam_boundary(DiskCut& cut, std::uint32_t size);
// Gives every border pixel of a size x size image of a map on seam_boundary the mean position of
// its pixel and those joined with it through `mate`; returns the border pixels changed.
std::size_t join_seam(PositionImage& image, const std::vector<std::uint32_t>& mate);
// The mesh rebuilt from such an image, closed over the seam: its vertices at identical positions
// (the joined border pixels) merged, faces left with a repeated vertex dropped, normals recomputed.
// Returns the vertices merged away.
std::size_t close_seam(geo::Mesh& reconstruction);
// The border pixel of perimeter step s, as (column, row from the top).
glm::uvec2 border_pixel(std::uint32_t step, std::uint32_t size);
// The mesh `rebuild` makes of an image of a map on seam_boundary, joined over the seam (join_seam on
// the image, close_seam on the mesh) where the closed mesh is one manifold, oriented piece. With a
// pixel or two a path, copies of one cut vertex can fall on pixels that one quad touches, and the
// closed mesh would pinch there: then the image and the mesh stay open (`joined` false). Without a
// seam, the image's mesh as it is.
struct SeamJoin {
    geo::Mesh mesh;
    bool joined = false;
    std::size_t joined_pixels = 0, merged_vertices = 0;
};
SeamJoin rebuild_over_seam(PositionImage& image, const std::optional<SeamBoundary>& seam,
                           const std::function<geo::Mesh(const PositionImage&)>& rebuild);

enum class ParameterizeVariant { Tutte, Floater, Stretch, Density, Uniform3d, Curvature };
const char* variant_name(ParameterizeVariant variant);  // "tutte", "floater", ...
std::optional<ParameterizeVariant> parse_variant(const std::string& name);

struct ParameterizeOptions {
    ParameterizeVariant variant = ParameterizeVariant::Curvature;
    std::optional<std::array<std::uint32_t, 4>> corners;  // boundary vertices for the square's corners
    std::optional<SquareBoundary> boundary;               // the whole boundary's place (seam_boundary)
    std::size_t max_iterations = 50;
    // Stop when E_sigma (the mean of |sigma_ij - 1|^2 over the directed edges of interior rows)
    // falls by less than this fraction in one iteration; for `stretch`, when the L2 stretch does.
    double stop_fall = 0.01;
    // A rise of E_sigma ends the run too (the thesis's rule). cut_and_map turns this off for a mesh
    // it cut: Floater's map of a cut surface crushes whole parts (L2 stretch up to 1e8), and E_sigma
    // can rise for many iterations while the reweighting opens them (femur: from the fourth, while
    // its image improves from 39 to 55 dB); the run then ends at a fall of less than stop_fall, at
    // max_iterations, or at a fold.
    bool rise_ends_run = true;
    // N in C = (k1^2 + k2^2)^(1/N) (6.13). The thesis chose 3 to 4 per model; on the shared disk
    // meshes 6 keeps more detail at every image size (docs/gim.md has the sweep).
    double curvature_root = 6.0;
    // The corner x4 and boundary x2 factors on uniform3d's and curvature's ratios as well, as the
    // thesis prints it. Off by default: the 3D one-ring is cut by the boundary as the 2D one is,
    // so the ratio needs no correction (and a planar square then maps to itself).
    bool boundary_factors_on_ratio = false;
    double solve_tolerance = 1e-8;  // relative residual of the map returned
    // Relative residual of the reweighting's iterates: the returned map's weights are then solved
    // again to solve_tolerance, from the iterate. An iterate that folds at this tolerance is solved
    // to solve_tolerance at once (its negative areas would break the next reweighting), and on to
    // fold_tolerance if it still folds (parts crushed below what solve_tolerance resolves: Floater's
    // map of dino opened along a seam turns 168 triangles over at 1e-8, none at 1e-11). One that
    // folds even there ends the
    // run, and the last iterate that does not fold is returned (for stretch, the one of least L2
    // stretch, which never folds).
    double iterate_tolerance = 1e-5;
    double fold_tolerance = 1e-11;
    // Most BiCGSTAB iterations of one solve; a solve that has not reached its tolerance by then
    // fails (Parameterization::unsolved).
    std::size_t max_solver_iterations = 20'000;
    // Keep every iterate's map (Parameterization::iterates), for choosing one by another measure;
    // every iterate is then solved to solve_tolerance.
    bool keep_iterates = false;
    // Return the iterate whose select_size x select_size geometry image rebuilds the mesh best
    // (geometry_image_rms with select_samples samples each way, on the CPU) instead of the last one
    // (stretch: instead of the one of least L2 stretch). 0: off. Iterate 0, Floater's map, is a
    // candidate, so by that measure the map returned is never worse than the start.
    std::uint32_t select_size = 0;
    std::size_t select_samples = 50'000;
    // Without select_size: measure three candidates as select does (with 10,000 samples each way),
    // at this size, and return the one that rebuilds the mesh best: the iterate the rule returns,
    // the start (Floater's map) and the iterate of least E_sigma that does not fold. cut_and_map sets
    // it on a surface it cut, where reweighting can crush parts that the start keeps, or run on
    // through a rise of E_sigma past its best.
    std::uint32_t candidates_size = 0;
};

struct IterationReport {
    std::size_t iteration = 0;          // 0: the Floater (or Tutte) start
    double sigma_error = 0.0;           // E_sigma of the factors applied to reach this iterate (0 at 0)
    double area_spread = 0.0;           // standard deviation of log(A_i / mean A), interior vertices
    double l2_stretch = 0.0;            // Sander's L2 stretch of the map, 2D area scaled to the 3D area
    std::size_t flipped = 0;            // parameter triangles of negative area
    std::size_t solver_iterations = 0;  // both solves where an iterate folded at the iterate tolerance
    double seconds = 0.0;               // reweighting and solve of this iteration
    double solve_seconds = 0.0;         // of seconds: the linear solves (system, upload, iterations, result)
    double image_rms = 0.0;             // with select_size: geometry_image_rms of this iterate (with
                                        // candidates_size: of the candidates measured; else 0)
};

struct Parameterization {
    std::vector<glm::dvec2> uv;  // per vertex, in [0, 1]^2: the last iterate (stretch: the best by L2 stretch)
    SquareBoundary boundary;
    std::vector<IterationReport> iterations;
    std::vector<std::vector<glm::dvec2>> iterates;  // with keep_iterates: every iterate's uv, 0 first
    std::size_t final_solver_iterations = 0;        // the returned map's solve to solve_tolerance
    std::size_t selected = 0;                       // the iterate returned
    // The iterate the run would return before candidates_size's candidates are measured (with
    // select_size, the one select chose); selected where no other candidate won.
    std::size_t rule_iteration = 0;
    // Where a reweighted iterate's solve failed ("iteration T: " and the solver's message), which
    // ended the run; empty otherwise.
    std::string unsolved;
    double seconds = 0.0;                           // the whole run, set-up included
    double solve_seconds = 0.0;                     // of seconds: every linear solve, the final one's included
    // GPU path: the queue submissions the run made and, of seconds, the host's time waiting for them
    // (Context::submission_count and device_wait_seconds); 0 for the CPU twin.
    std::uint64_t submissions = 0;
    double device_wait_seconds = 0.0;
};

// The map on the GPU (the solver module's BiCGSTAB, each solve warm-started from the last) or, with
// ctx == nullptr, with the CPU twin of the same solver. Throws geo::InputError for a mesh that is
// not a disk (check_disk_mesh) and when the start's or the returned map's solve fails; a reweighted
// iterate whose solve fails ends the run instead (Parameterization::unsolved).
Parameterization parameterize_square(Context* ctx, const geo::Mesh& mesh, const ParameterizeOptions& options = {},
                                     const std::function<void(const IterationReport&)>& on_iteration = {});

// A mesh cut open (cut_to_disk), its boundary placed for joining the seam (seam_boundary; the map's
// corners and boundary come from there) and mapped (parameterize_square). With
// options.select_size and no graph named in cut_options, on a surface where the two initial cut
// graphs differ (neither a sphere nor a disk) each is cut and mapped, and the one kept is the one
// whose selected iterate's image rebuilds the mesh better (image_rms); the lower stretch alone
// picks the better map on 10 of the 14 shared meshes with two graphs (docs/gim.md).
struct CutMap {
    DiskCut cut;
    std::optional<SeamBoundary> seam;
    Parameterization map;
    double cut_seconds = 0.0;             // in cut_to_disk (both calls where both graphs were mapped)
    std::vector<double> graph_image_rms;  // where both were mapped: FaceTree's, ShortestLoops'
};
CutMap cut_and_map(Context* ctx, const geo::Mesh& mesh, std::uint32_t size, const ParameterizeOptions& options,
                   const DiskCutOptions& cut_options = {});

// Per vertex, the feature measure of the curvature variant: C_i = (k1^2 + k2^2)^(1/root) on the
// mesh scaled to a unit bounding-box diagonal, smoothed twice by the bilateral filter of (6.14) with
// the sign corrected (sigma_L = 0.1, sigma_D = 2).
std::vector<double> curvature_feature(const geo::Mesh& mesh, const geo::MeshAdjacency& adjacency, double root = 6.0);

// Parameter triangles of negative signed area (folds).
std::size_t count_flipped(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv);

// The geometry image of a square map: an N x N grid, pixel (a, b) (b the row from the top) at the
// parameter point (a / (N - 1), 1 - b / (N - 1)), so the border lies on the boundary. The
// rasteriser leaves centres exactly on an edge to one side, so both paths sample the map grown
// about the square's centre by 1/64 pixel: border samples lie that far inside the boundary.
geo::Mesh square_grid_mesh(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv, std::uint32_t size);
PositionImage geometry_image_gpu(Context& ctx, const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv,
                                 std::uint32_t size);
PositionImage geometry_image_cpu(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv, std::uint32_t size);

// The side of the geometry image that `requested` asks for: itself, or for 0 round(sqrt(vertices)),
// the thesis's choice (about as many samples as vertices), within [2, 16384]. Throws
// geo::InputError for 1, which no geometry image can be.
std::uint32_t geometry_image_size(std::uint32_t requested, std::size_t vertices);

// How well a map's N x N geometry image keeps the mesh: the larger of the two one-sided RMS
// distances between the mesh and the image's reconstruction (reconstruct_cpu, never cut), relative
// to the mesh's bounding-box diagonal, each measured with `samples` area samples (surface_distance.h).
// CPU twins throughout, so the figure does not depend on the device.
double geometry_image_rms(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv, std::uint32_t size,
                          std::size_t samples);
// The same with the mesh's tree built once for many maps.
double geometry_image_rms(const geo::Mesh& mesh, const geo::TriangleBvh& mesh_bvh, const std::vector<glm::dvec2>& uv,
                          std::uint32_t size, std::size_t samples);
// The GPU path recorded into a caller's graph: `parameters` hold 2 float32 a vertex as
// square_grid_mesh places them (uv already on the image grid).
ImageHandle add_geometry_image(Graph& graph, BufferHandle positions, BufferHandle parameters, BufferHandle triangles,
                               std::uint32_t face_count, std::uint32_t size);

}  // namespace gimg::passes

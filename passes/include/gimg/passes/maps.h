#pragma once
// MAPS remeshing to 4-to-1 subdivision connectivity, and k-disk wavelets on the result (Miura,
// Kanai & Kishinami, after Lee et al., "MAPS", SIGGRAPH 1998; docs/maps.md). A closed mesh is
// simplified level by level (a maximal independent set of vertices removed in order of the
// priority w = lambda a/max a + (1 - lambda) kappa/max kappa, each hole re-triangulated in the
// removed vertex's flattened ring, angles scaled as z^a scales them) down to a base domain, every
// original vertex tracked as (triangle, barycentric) on each level; the base is then subdivided
// 4-to-1 and every new point mapped back onto the original surface. The remesh is analysed by
// piecewise-linear k-disk wavelets (Lounsbery, DeRose & Warren 1997): predict by edge midpoints,
// update by the local orthogonalisation weights s_{i,m}.

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/mesh.h"

#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

namespace gimg::passes {

// ---- Base domain and parameter tracking (sec. 2.2-2.3) ----

enum class RingFlattening { Polar, Za };

struct MapsOptions {
    double lambda = 0.5;              // weight of the ring area against the curvature in the priority
    std::uint32_t base_vertices = 0;  // stop at this many vertices; 0: V / 20 within 50 (1 + g), 150 (1 + g)
    std::uint32_t max_valence = 12;   // vertices of higher valence are never removed
    bool check_tracking = false;      // assert the tracking invariants after every removal (tests)
    bool keep_levels = false;         // keep every level's triangles in BaseDomain::level_faces
    // The ring flattening's radii: Polar r_k (the default), or the paper's z^a, r_k^a. Both scale
    // the angles by a = 2 pi / total angle. z^a shrinks the ring of a cone tip as r^a, and the
    // shrinking compounds level after level: protrusions end up undersampled (docs/maps.md).
    RingFlattening flattening = RingFlattening::Polar;
    // A vertex whose a exceeds this, or falls below its inverse, is not removed: a cone tip
    // (total angle below 2 pi / max_cone) stays, so long protrusions keep base vertices. 0: none.
    double max_cone = 2.0;
    // Remesh smoothing (an extension; the paper has none): iterations moving every point inside a
    // base triangle halfway to the 3D-edge-length-weighted mean of its neighbours there, each
    // followed by a new evaluation of the points; the points on base edges stay.
    std::uint32_t smoothing = 0;
};

// Where a point of the original surface lies on a level: a triangle of that level and barycentric
// coordinates in it (non-negative, summing to 1).
struct SurfacePoint {
    std::uint32_t face = 0;
    glm::dvec3 bary{1.0, 0.0, 0.0};
};

struct MapsLevel {
    std::uint32_t vertices = 0;    // |P^l| after the level
    std::uint32_t removed = 0;     // vertices removed by the level
    std::uint32_t candidates = 0;  // independent vertices considered
    std::uint32_t skipped = 0;     // of them, refused: a cone tip, a refill degenerate or duplicating an edge, valence
    double seconds = 0.0;
};

// The base domain K^0 and the map Pi = Pi^0 from the original mesh onto it.
struct BaseDomain {
    geo::Mesh base;                                        // base vertices at their original positions
    std::vector<std::uint32_t> original;                   // per base vertex: its vertex in the original mesh
    std::vector<SurfacePoint> param;                       // per original vertex: its image in the base domain
    std::vector<MapsLevel> levels;                         // from the original downwards
    std::vector<std::vector<std::uint32_t>> removed_sets;  // per level: the removed vertices (original ids)
    std::vector<std::vector<glm::uvec3>> level_faces;      // with keep_levels: K^l after each level, original ids
};

// Throws geo::InputError when the mesh is not a closed 2-manifold with consistent orientation.
BaseDomain build_base_domain(const geo::Mesh& mesh, const MapsOptions& options = {});

// ---- Semi-regular remesh (sec. 2.4) ----

// The base domain subdivided 4-to-1 `levels` times. Vertex ids are nested: level j uses the ids
// 0 .. vertex_count[j] - 1, level 0 being the base vertices. Every vertex added by level j + 1
// (an odd vertex m) is the midpoint of a level-j edge parents[m - vertex_count[0]].
struct SemiRegularMesh {
    std::vector<std::vector<glm::uvec3>> faces;  // per level 0..J, counter-clockwise
    std::vector<std::uint32_t> vertex_count;     // per level 0..J
    std::vector<glm::uvec2> parents;             // per odd vertex, ids below vertex_count[j]
    std::vector<SurfacePoint> base_point;        // per vertex: its base triangle and barycentric coordinates
    std::vector<glm::dvec3> positions;           // per vertex of the finest level (empty until mapped)

    std::uint32_t levels() const { return std::uint32_t(faces.size()) - 1; }
    // Level j as a mesh: the first vertex_count[j] positions and faces[j].
    geo::Mesh level_mesh(std::uint32_t j) const;
};

// Topology and base coordinates only; positions stay empty. `levels` at most 8.
SemiRegularMesh subdivide_base(const geo::Mesh& base, std::uint32_t levels);

// Pi^{-1} made searchable: every original triangle's image in a planar chart, a base triangle's
// own barycentric plane when its three corners map into that triangle, otherwise the z^a
// flattening of a base vertex whose star holds all three (a pair of base triangles sharing an
// edge is in the stars of both ends). Each chart buckets its triangles in a uniform grid. A point
// of base triangle f is looked up in f's chart, then in its corners' charts, largest barycentric
// coordinate first; the first image triangle holding it gives its position on the original.
struct InverseMap {
    std::vector<std::uint32_t> face_charts;    // per base face: its own chart, its 3 corners' charts, its 3
                                               // corners' original vertices, 0
    std::vector<glm::dvec2> corner_coords;     // per base face, per corner chart (3) and corner (3)
    std::vector<glm::dvec4> chart_box;         // per chart: grid origin (x, y) and cell size (x, y)
    std::vector<glm::uvec4> chart_grid;        // per chart: cells in x, cells in y, first cell, 0
    std::vector<std::uint32_t> cell_offsets;   // CSR over every chart's cells
    std::vector<std::uint32_t> cell_items;     // indices into triangle_face / triangle_coords
    std::vector<glm::dvec2> triangle_coords;   // 3 per chart triangle
    std::vector<std::uint32_t> triangle_face;  // per chart triangle: its original face
    std::size_t straddling = 0;                // original triangles whose corners lie in different base triangles
    std::size_t unplaced = 0;                  // of them, no base vertex's star holds all three (not searchable)
    std::size_t inverted = 0;                  // chart triangles of negative area (0 for a bijective map)
};

InverseMap build_inverse_map(const geo::Mesh& mesh, const BaseDomain& domain);

// Positions on the original surface of the given base points (CPU). `fallbacks`, when given,
// counts the points found in no image triangle: placed in the nearest one instead, or, where a
// base triangle's charts hold none, at the original surface's point nearest the flat point
// between the base triangle's corners.
std::vector<glm::dvec3> evaluate_inverse_map(const geo::Mesh& mesh, const InverseMap& map,
                                             const std::vector<SurfacePoint>& points, std::size_t* fallbacks = nullptr);

// The same as one compute pass: `points` holds per point its base face (uint) and
// `bary` 3 doubles each; `out` receives 4 doubles per point: the position and a flag (0 found,
// 1 placed in the nearest image triangle, -1 none). The map's arrays and the original mesh are on
// the device in texel arrays (gimg/engine/texel_array.h; upload_inverse_map says how each is packed).
struct InverseMapBuffers {
    Image face_charts, corner_coords, chart_box, chart_grid, cell_offsets, cell_items, triangle_coords, triangle_face,
        positions, faces;
};
InverseMapBuffers upload_inverse_map(Context& ctx, const geo::Mesh& mesh, const InverseMap& map);
void add_inverse_map(Graph& graph, InverseMapBuffers& map, BufferHandle points, BufferHandle bary, BufferHandle out,
                     std::uint32_t count);
std::vector<glm::dvec3> evaluate_inverse_map_gpu(Context& ctx, const geo::Mesh& mesh, const InverseMap& map,
                                                 const std::vector<SurfacePoint>& points,
                                                 std::size_t* fallbacks = nullptr);
// The same with the map already on the device (upload_inverse_map), for evaluating again and again.
std::vector<glm::dvec3> evaluate_inverse_map_gpu(Context& ctx, InverseMapBuffers& buffers, const geo::Mesh& mesh,
                                                 const InverseMap& map, const std::vector<SurfacePoint>& points,
                                                 std::size_t* fallbacks = nullptr);

// The whole remesh: base domain, `levels` 4-to-1 subdivisions, and every point of the finest
// level mapped back onto the original (on the GPU when ctx is given, else by the CPU twin); the
// coarser levels are the finest one's nested prefixes.
struct MapsRemesh {
    BaseDomain domain;
    SemiRegularMesh remesh;
    InverseMap map;
    std::size_t fallbacks = 0;  // points found in no image triangle (0 for a bijective map)
    double base_seconds = 0.0, subdivide_seconds = 0.0, locate_seconds = 0.0, evaluate_seconds = 0.0,
           smoothing_seconds = 0.0;
};
MapsRemesh maps_remesh(Context* ctx, const geo::Mesh& mesh, const MapsOptions& options, std::uint32_t levels);

// ---- k-disk wavelets (sec. 2.5) ----

// The analysis weights of one wavelet: k < 0 the lazy wavelet (no update: every row empty, k = -1),
// k = 0, 1, 2 the k-disk wavelet with D_0(m) = the parent edge's ends and D_k = D_{k-1} and its
// level-j one-ring (k > 2 throws geo::InputError). s_{., m} solves G s = b, G_il = <phi^j_i, phi^j_l>
// and b_i = <phi^j_i, phi^{j+1}_m> over D_k(m), every base triangle weighing the same.
// Per level j = 0 .. J-1 and per even vertex i < vertex_count[j]: the odd vertices m of level
// j + 1 whose D_k(m) holds i, with s_{i,m} (CSR, `offsets` of vertex_count[j] + 1 entries).
struct WaveletFilters {
    int k = 1;
    struct Level {
        std::vector<std::uint32_t> offsets;
        std::vector<std::uint32_t> odd;
        std::vector<double> weight;
    };
    std::vector<Level> levels;
};

WaveletFilters wavelet_filters(const SemiRegularMesh& mesh, int k);

// In place over one value per vertex of the finest level: analysis leaves the base coefficients
// c^0 in the first vertex_count[0] entries and the detail d of odd vertex m at entry m; synthesis
// undoes it. `down_to`: stop the analysis at that level (its coefficients c^j in the first
// vertex_count[j] entries), and start the synthesis there.
void wavelet_analysis(const SemiRegularMesh& mesh, const WaveletFilters& filters, std::vector<glm::dvec3>& values,
                      std::uint32_t down_to = 0);
void wavelet_synthesis(const SemiRegularMesh& mesh, const WaveletFilters& filters, std::vector<glm::dvec3>& values,
                       std::uint32_t from = 0);

// The same on the GPU on a buffer of 3 doubles per vertex (the values' new version is returned):
// the values are copied into a texel array, transformed there by one predict and, unless the level
// has no weights, one update dispatch per level, and copied back. The filters come from
// upload_wavelet_filters, are imported into the graph by each call and must outlive its plan.
// Needs shaderFloat64 (gimg::Error otherwise).
struct WaveletBuffers {
    // Texel arrays of 32-bit words (gimg/engine/texel_array.h), two words per uvec2 and per double.
    Image parents;                                            // uvec2 per odd vertex
    Image offsets;                                            // every level's CSR offsets, concatenated
    Image odd;                                                // every level's odd ids, concatenated
    Image weight;                                             // every level's s_{i,m}, concatenated
    std::vector<std::uint32_t> offsets_start, entries_start;  // per level where its arrays begin, then the totals
};
WaveletBuffers upload_wavelet_filters(Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters);
// Whether the device can run the transform on this mesh: shaderFloat64, and the values and every
// filter array within its texel-array rows (upload_wavelet_filters throws gimg::Error otherwise).
bool wavelets_fit_device(const Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters);
BufferHandle add_wavelet_analysis(Graph& graph, BufferHandle values, const SemiRegularMesh& mesh,
                                  WaveletBuffers& filters, std::uint32_t down_to = 0);
BufferHandle add_wavelet_synthesis(Graph& graph, BufferHandle values, const SemiRegularMesh& mesh,
                                   WaveletBuffers& filters, std::uint32_t from = 0);
// Uploads the filters and the values, runs the transform and reads the values back.
std::vector<glm::dvec3> wavelet_analysis_gpu(Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters,
                                             const std::vector<glm::dvec3>& values, std::uint32_t down_to = 0);
std::vector<glm::dvec3> wavelet_synthesis_gpu(Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters,
                                              const std::vector<glm::dvec3>& values, std::uint32_t from = 0);
// The same with the filters already on the device, for transforming again and again.
std::vector<glm::dvec3> wavelet_analysis_gpu(Context& ctx, const SemiRegularMesh& mesh, WaveletBuffers& filters,
                                             const std::vector<glm::dvec3>& values, std::uint32_t down_to = 0);
std::vector<glm::dvec3> wavelet_synthesis_gpu(Context& ctx, const SemiRegularMesh& mesh, WaveletBuffers& filters,
                                              const std::vector<glm::dvec3>& values, std::uint32_t from = 0);

// Keeps the largest `fraction` of the detail coefficients of a full analysis (rounded to a count),
// zeroing the rest; the base coefficients are always kept. A detail d^j_m counts as |d^j_m| 2^-(j+1):
// the norm of phi^{j+1}_m in the equal-weight inner product (an odd vertex has six triangles of
// normalised area 4^-(j+1)), so its size when zeroed alone for the lazy wavelet; the k-disk psi_m
// are shorter by a valence-dependent factor (about 0.84 for k = 0 among valence 6), and wavelets are
// not mutually orthogonal, so the ranking is a close heuristic. Returns how many details were kept.
std::size_t keep_largest_details(const SemiRegularMesh& mesh, std::vector<glm::dvec3>& coefficients, double fraction);

}  // namespace gimg::passes

#pragma once
// Four-sided regions of any mesh mapped onto the unit square, and deformations through that map
// (Kuriyama & Kaneko, "Deformation via discrete parametrization of a quadrilateral region";
// docs/quadmap.md). Four corner vertices W1..W4 span the region: each side is the mesh cut by the
// plane through W_i and W_i+1 spanned by (W_i - W_i+1) and (N_i + N_i+1), with points inserted
// where it crosses edges. The region is mapped with Floater's (or chord-length) weights, the
// corners going to (0,0), (1,0), (1,1), (0,1), solved by the paper's relaxation (Gauss-Seidel in
// colour order, a dispatch per colour) from a flat or an accelerated start (Dijkstra distances and
// a bilinear normalisation, by default followed by over-relaxed sweeps), by the solver module's
// BiCGSTAB on the GPU, or by Eigen's SparseLU; and deformed by a lattice of offsets (clamped cubic
// B-splines, the outer layers fixed) or by a pasted height along the normals.

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/mesh.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace gimg::passes {

inline constexpr std::uint32_t kInsertedNode = 0xffffffffu;

// The region as its own mesh: the faces of the original on the left of W1 -> W2 -> W3 -> W4, those
// crossed by a side split along it. Vertices are original vertices or points inserted on edges.
struct QuadRegion {
    geo::Mesh mesh;                          // the region; counter-clockwise like the original
    std::vector<std::uint32_t> original;     // per region vertex: its original vertex, or kInsertedNode
    std::array<std::uint32_t, 4> corners{};  // W1..W4 (W1..W3 for a triangle) as region vertex indices
    std::uint32_t corner_count = 4;          // 3 for a triangle region (cut_triangle_region)
    std::vector<std::uint8_t> side;          // per region vertex: 0 inside, i on side W_i -> W_i+1
    std::size_t inserted = 0;                // points inserted on edges
    std::size_t merged = 0;                  // crossings close to a vertex that took the vertex instead
    std::size_t fallback_sides = 0;          // sides whose plane section failed, taken as shortest edge paths
    geo::Mesh outside;                       // the rest of the mesh, split the same way (for pictures)
};

// Throws geo::InputError with the reason when the corners are not four distinct vertices, a side
// cannot be traced (it leaves the mesh), the sides cross or do not enclose a disk on their left.
QuadRegion cut_quad_region(const geo::Mesh& mesh, const std::array<std::uint32_t, 4>& corners);

// The three-sided region of three corners (sec. 4.2, barycentric coordinates), cut the same way.
QuadRegion cut_triangle_region(const geo::Mesh& mesh, const std::array<std::uint32_t, 3>& corners);

// The same with the mesh's adjacency and face normals built once, for cutting again and again (the
// mesh must outlive it).
class QuadRegionCutter {
public:
    explicit QuadRegionCutter(const geo::Mesh& mesh);
    // outside = false leaves QuadRegion::outside empty (it is only for pictures, and costs a pass
    // over the whole mesh).
    QuadRegion cut(const std::array<std::uint32_t, 4>& corners, bool outside = true) const;
    QuadRegion cut_triangle(const std::array<std::uint32_t, 3>& corners, bool outside = true) const;
    const geo::Mesh& mesh() const { return *mesh_; }
    const geo::MeshAdjacency& adjacency() const { return adjacency_; }

private:
    QuadRegion cut_polygon(const std::vector<std::uint32_t>& corners, bool outside) const;
    const geo::Mesh* mesh_;
    geo::MeshAdjacency adjacency_;
    std::vector<glm::dvec3> face_normals_;
    std::vector<std::uint32_t> face_across_;  // per face edge: the face across it (region_cut.cpp)
    double diagonal_;
};

enum class QuadWeights { Floater, Chord };
// Flat: 0.5 on every free vertex. Dijkstra: the paper's accelerated start. Overrelaxed: the
// accelerated start, then kOverrelaxedSweeps sweeps of eq. (2) over-relaxed (k = 1 - omega,
// omega = kOverrelaxation), which take out most of the smooth error the relaxation is slow on.
enum class QuadStart { Flat, Dijkstra, Overrelaxed };
inline constexpr std::size_t kOverrelaxedSweeps = 40;
inline constexpr double kOverrelaxation = 1.8;
enum class QuadSolver { Iterate, Krylov, Direct };

struct QuadMapOptions {
    QuadWeights weights = QuadWeights::Floater;
    QuadStart start = QuadStart::Overrelaxed;
    QuadSolver solver = QuadSolver::Krylov;
    double relaxation = 0.05;  // k of eq. (2) and (4)
    double tau = 1e-4;         // eq. (2) stops when every correction is below tau
    std::size_t max_sweeps = 100000;
    double krylov_tolerance = 1e-10;
};

struct QuadMap {
    std::vector<glm::dvec2> uv;     // per region vertex
    std::vector<glm::dvec2> start;  // the initial guess the solver started from
    // The accelerated start of eq. (3) and (4) (flat: 0.5 inside), before a warm start and the
    // over-relaxed sweeps.
    std::vector<glm::dvec2> accelerated;
    std::size_t iterations_u = 0;  // sweeps of eq. (2) for u (Iterate), solver iterations (Krylov)
    std::size_t iterations_v = 0;
    std::size_t start_sweeps = 0;  // sweeps of eq. (4) in the accelerated start
    // The corners' distances fold eq. (3) (s1 / s0 + t1 / t0 <= 1: a dart-shaped region), and the
    // accelerated start took the root nearest the linear guess.
    bool start_folded = false;
    std::size_t overrelaxed_sweeps = 0;  // over-relaxed sweeps of the start (0: none, or they diverged)
    std::size_t weight_fallbacks = 0;    // vertices whose flattened star had no containing triangle
    std::size_t flipped = 0;             // region triangles of negative area in (u, v)
    double weights_ms = 0.0, start_ms = 0.0, solve_ms = 0.0;
};

// The map of a region; with ctx == nullptr the relaxation and the Krylov solve run on their CPU
// twins. `warm`: per region vertex a correction added to the accelerated start (NaN where there is
// none), such as the last map's uv - accelerated of the same vertex: after a corner moved, the
// accelerated start follows the new square and the correction keeps what the last solve found.
QuadMap map_quad_region(Context* ctx, const QuadRegion& region, const QuadMapOptions& options = {},
                        const std::vector<glm::dvec2>& warm = {});

// Barycentric coordinates (alpha, beta, gamma) of a triangle region's vertices (sec. 4.2): three
// solves with the same weights, the alpha one with alpha = 1 at W1, 0 on the side W2 W3 and chord
// length along the two others (likewise beta, gamma), each then divided by their sum. With
// ctx == nullptr, SparseLU; else the solver module's BiCGSTAB on the GPU.
std::vector<glm::dvec3> barycentric_map(Context* ctx, const QuadRegion& triangle,
                                        QuadWeights weights = QuadWeights::Floater);

// Chord-length weights: lambda_j proportional to 1 / |P_j - P_i| (same layout as floater_weights).
std::vector<double> chord_weights(const geo::Mesh& mesh, const geo::MeshAdjacency& adjacency);

// Corners for trying a region out (`gimg quadmap --corners auto`): a square of side `side` times
// the bounding-box diagonal around the flattest interior vertex (least k1^2 + k2^2 summed over its
// ring), corners counter-clockwise seen along its normal, on that vertex's piece of the mesh. Where
// the square is wider than the part it sits on, its sides run round that part and their left is the
// rest of the mesh; a region of more than half the mesh's area is therefore taken the other way
// round where that cuts. Where the square's sides cut no disk (they cross, or enclose a handle or a
// hole), the side is halved, up to four times; past that, geo::InputError says so.
// The cutter's mesh and adjacency serve both the choice and the trial cuts.
std::array<std::uint32_t, 4> flattest_square_corners(const QuadRegionCutter& cutter, double side = 0.2);

// Dijkstra's distances along the region's edges from the u = 0 side (s, first) and from the v = 0
// side (t), each side a virtual source; `adjacency` is the region mesh's.
std::array<std::vector<double>, 2> side_distances(const QuadRegion& region, const geo::MeshAdjacency& adjacency);

// The accelerated start (sec. 3): Dijkstra distances s, t from the u = 0 and v = 0 sides, eq. (3)
// inverted in closed form, then at most 3 sweeps of eq. (4). `adjacency` is the region mesh's.
// Returns the sweeps used; `folded` says whether eq. (3) folds on this region.
std::size_t dijkstra_start(const QuadRegion& region, const geo::MeshAdjacency& adjacency,
                           const std::vector<glm::dvec2>& boundary_uv, double relaxation, double tau,
                           std::vector<glm::dvec2>& uv, bool* folded = nullptr);
// Eq. (3): (s, t) from (u, v), and its inverse (the stable root; the fold-free case is
// s1 / s0 + t1 / t0 > 1, otherwise the root nearest (s / s0, t / t0) in the square, and `folded`).
glm::dvec2 bilinear_forward(glm::dvec2 uv, double s0, double t0, double s1, double t1);
glm::dvec2 bilinear_inverse(glm::dvec2 st, double s0, double t0, double s1, double t1, bool* folded = nullptr);

// Offsets: F(u, v) = sum_pq O_pq B_p(u) B_q(v), clamped cubic B-splines on [0, 1] with
// columns x rows control points (at least 4 each way). Those in the outer L + 1 rows and columns
// of each side, L = fixed_layers, are zero: L = 2 makes F, its first and its second derivatives
// vanish at the region's boundary (C2); -1 fixes none.
struct OffsetLattice {
    std::uint32_t columns = 8, rows = 8;
    std::vector<glm::dvec3> offsets;  // columns * rows, row-major (q * columns + p)
    int fixed_layers = 2;
    glm::dvec3 evaluate(glm::dvec2 uv) const;  // with the fixed layers zeroed
};

// Polar coordinates on the square (sec. 4.2): centre (1/2, 1/2), r = 2 |(u, v) - centre| (1 on
// the inscribed circle), theta = atan2(v - 1/2, u - 1/2) in [0, 2 pi).
glm::dvec2 polar_coordinates(glm::dvec2 uv);

// Offsets on a concentric lattice: F = sum_pq O_pq B_p(r) C_q(theta), B clamped cubic B-splines on
// r in [0, 1] (`rings` control points), C periodic uniform cubic B-splines in theta (`sectors`
// control points). The outer three rings are fixed at zero (C2 at r = 1), and so are the inner
// three (F does not depend on theta at the centre); nothing moves beyond r = 1. At least 7 rings
// (one free) and 3 sectors.
struct PolarLattice {
    std::uint32_t rings = 9, sectors = 8;
    std::vector<glm::dvec3> offsets;  // rings * sectors, ring-major (p * sectors + q)
    glm::dvec3 evaluate(glm::dvec2 uv) const;
};
geo::Mesh deform_by_polar_lattice(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                                  const PolarLattice& lattice);

// A height field along the normals: G(u, v) from a height map (bilinear, [0, 1]^2 over the image)
// or the built-in bump h (4u(1 - u))^3 (4v(1 - v))^3.
struct PastedFeature {
    std::uint32_t width = 0, height = 0;
    std::vector<float> heights;  // width * height, row 0 at v = 1; empty: the built-in bump
    double scale = 0.1;          // h, in units of the mesh's bounding-box diagonal
    double evaluate(glm::dvec2 uv) const;
};

// The deformed original mesh: P'_i = P_i + F(u_i, v_i) for the region's original vertices, every
// other vertex unchanged. The GPU path is a compute pass; the CPU twin gives the same positions.
geo::Mesh deform_by_lattice(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                            const OffsetLattice& lattice);
geo::Mesh paste_feature(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                        const PastedFeature& feature);
// The GPU path: one compute pass over the region's vertices, in the CPU twin's order of operations.
geo::Mesh deform_by_lattice_gpu(Context& ctx, const geo::Mesh& mesh, const QuadRegion& region,
                                const std::vector<glm::dvec2>& uv, const OffsetLattice& lattice);
geo::Mesh paste_feature_gpu(Context& ctx, const geo::Mesh& mesh, const QuadRegion& region,
                            const std::vector<glm::dvec2>& uv, const PastedFeature& feature);

// The deformation recorded into a caller's graph. positions: 3 float64 per mesh vertex, moved in
// place; normals: 3 float64 per mesh vertex, unit (paste only); original: a uint32 per region vertex
// (kInsertedNode for inserted points); uv: 2 float64 per region vertex; offsets: 3 float64 per
// control point with the fixed layers zero (lattice); heights: float32, row 0 at v = 1 (height map).
// Buffers a mode does not read may be any buffer of 16 bytes.
struct QuadDeformation {
    enum class Kind : std::uint32_t { Lattice, Bump, HeightMap } kind = Kind::Lattice;
    std::uint32_t region_vertices = 0;
    std::uint32_t columns = 0, rows = 0;  // the lattice, or the height map's width and height
    double scale = 0.0;                   // paste: the height in model units
};
void add_quad_deformation(Graph& graph, BufferHandle positions, BufferHandle normals, BufferHandle original,
                          BufferHandle uv, BufferHandle offsets, BufferHandle heights, const QuadDeformation& what);

class LatticeWeights;  // passes/quad_region/lattice_weights.h

// Interactive editing: the mesh and its adjacency are kept; moving a corner re-cuts the region and
// re-solves from the last map (every vertex still in the region starts from the new accelerated
// start plus the last map's correction to its own); changing the offsets only re-evaluates the
// deformation, from basis values kept per map.
class QuadRegionEditor {
public:
    QuadRegionEditor(Context* ctx, geo::Mesh mesh, const std::array<std::uint32_t, 4>& corners,
                     QuadMapOptions options = {});
    QuadRegionEditor(const QuadRegionEditor&) = delete;  // the cutter points at the editor's mesh
    QuadRegionEditor& operator=(const QuadRegionEditor&) = delete;
    // Re-cut with corner i (0..3) at `vertex`, re-map, re-deform; returns the deformed mesh.
    const geo::Mesh& move_corner(int i, std::uint32_t vertex);
    const geo::Mesh& set_lattice(const OffsetLattice& lattice);
    const QuadRegion& region() const { return region_; }
    const QuadMap& map() const { return map_; }
    const geo::Mesh& deformed() const { return deformed_; }

private:
    void remap(const std::vector<glm::dvec2>& previous_by_vertex);
    void deform();
    Context* ctx_;
    geo::Mesh mesh_;
    QuadRegionCutter cutter_;
    std::array<std::uint32_t, 4> corners_;
    QuadMapOptions options_;
    QuadRegion region_;
    QuadMap map_;
    OffsetLattice lattice_;
    std::shared_ptr<const LatticeWeights> weights_;  // the lattice's basis values at map_.uv
    geo::Mesh deformed_;
};

}  // namespace gimg::passes

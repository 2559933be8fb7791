// Four-sided regions (Kuriyama & Kaneko): the spec's checks (sec. 1.13) — weights, an irregular
// planar square that maps to itself, fold-free maps on curved meshes, the relaxation's fixed point
// against the direct solve, the accelerated start (exact on a structured rectangle, eq. (3)'s round
// trip, far fewer sweeps), sides on their planes, and the deformations' boundary behaviour.
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/normals.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/quad_region.h"
#include "quad_region/relax_layout.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <tuple>

using namespace gimg;
namespace gp = gimg::passes;

namespace {

class QuadRegion : public gimg::test::GpuTest {};

// A planar sheet over [-0.5, 1.5]^2 (squares x squares), interior vertices jittered by up to
// `amount` except those at the unit square's corners.
geo::Mesh jittered_sheet(int squares = 20, double amount = 0.03, unsigned seed = 7) {
    geo::Mesh m = geo::make_grid(squares, squares, 2.0, 2.0);
    m.texcoords.clear();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-amount, amount);
    for (auto& p : m.positions) {
        p -= glm::dvec3(0.5, 0.5, 0.0);
        const bool edge = std::abs(p.x) > 1.49 || std::abs(p.y) > 1.49;
        const bool corner =
            (std::abs(p.x) < 1e-9 || std::abs(p.x - 1) < 1e-9) && (std::abs(p.y) < 1e-9 || std::abs(p.y - 1) < 1e-9);
        if (!edge && !corner) p += glm::dvec3(jitter(rng), jitter(rng), 0.0);
    }
    return m;
}

std::uint32_t nearest(const geo::Mesh& m, glm::dvec3 p) {
    std::uint32_t best = 0;
    for (std::uint32_t v = 0; v < m.vertex_count(); ++v)
        if (glm::distance(m.positions[v], p) < glm::distance(m.positions[best], p)) best = v;
    return best;
}

std::array<std::uint32_t, 4> unit_corners(const geo::Mesh& m) {
    return {nearest(m, {0, 0, 0}), nearest(m, {1, 0, 0}), nearest(m, {1, 1, 0}), nearest(m, {0, 1, 0})};
}

double max_error_xy(const gp::QuadRegion& r, const std::vector<glm::dvec2>& uv) {
    double worst = 0.0;
    for (std::size_t i = 0; i < uv.size(); ++i)
        worst = std::max(worst, glm::length(uv[i] - glm::dvec2(r.mesh.positions[i].x, r.mesh.positions[i].y)));
    return worst;
}

// Corners found on bunny by `gimg quadmap --corners auto` (a patch of its back).
constexpr std::array<std::uint32_t, 4> kBunnyCorners{203, 8848, 17085, 3857};

}  // namespace

TEST_F(QuadRegion, AnIrregularPlanarSquareMapsToItself) {
    // The unit square meshed irregularly, corners at its corners: the region is the whole mesh.
    geo::Mesh square = geo::make_grid(12, 12);
    square.texcoords.clear();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> jitter(-0.03, 0.03);
    for (auto& p : square.positions)
        if (p.x > 0.0 && p.x < 1.0 && p.y > 0.0 && p.y < 1.0) p += glm::dvec3(jitter(rng), jitter(rng), 0.0);
    const gp::QuadRegion r = gp::cut_quad_region(square, {0, 12, 168, 156});
    ASSERT_EQ(r.mesh.vertex_count(), square.vertex_count());
    // Floater's weights reproduce the plane: u = x, v = y by every solver.
    EXPECT_LE(max_error_xy(r, gp::map_quad_region(nullptr, r, {.solver = gp::QuadSolver::Direct}).uv), 1e-10);
    EXPECT_LE(max_error_xy(r, gp::map_quad_region(&ctx(), r, {.krylov_tolerance = 1e-12}).uv), 1e-9);
    const gp::QuadMap relaxed =
        gp::map_quad_region(nullptr, r, {.solver = gp::QuadSolver::Iterate, .tau = 1e-13, .max_sweeps = 200000});
    EXPECT_LE(max_error_xy(r, relaxed.uv), 1e-9);
    // Chord-length weights do not.
    EXPECT_GT(
        max_error_xy(
            r,
            gp::map_quad_region(nullptr, r, {.weights = gp::QuadWeights::Chord, .solver = gp::QuadSolver::Direct}).uv),
        1e-4);
}

TEST(QuadRegionCut, StraightSidesThroughAnIrregularSheet) {
    // The unit square inside a larger jittered sheet: each side's plane is vertical through two
    // corners, so inserted points lie on the square's sides and merged vertices within 5 % of an
    // edge (0.1 long here) of them.
    const geo::Mesh sheet = jittered_sheet();
    const gp::QuadRegion r = gp::cut_quad_region(sheet, unit_corners(sheet));
    EXPECT_GT(r.inserted, 20u);
    for (std::size_t i = 0; i < r.mesh.vertex_count(); ++i) {
        if (!r.side[i]) continue;
        const glm::dvec3 p = r.mesh.positions[i];
        const double off = std::min({std::abs(p.x), std::abs(p.x - 1), std::abs(p.y), std::abs(p.y - 1)});
        EXPECT_LT(off, r.original[i] == gp::kInsertedNode ? 1e-12 : 0.1 * 0.05 + 0.03) << i;
    }
    const gp::QuadMap m = gp::map_quad_region(nullptr, r, {.solver = gp::QuadSolver::Direct});
    EXPECT_EQ(m.flipped, 0u);
    EXPECT_LT(max_error_xy(r, m.uv), 0.02);  // the merged vertices bend the sides a little
}

TEST(QuadWeights, ChordLengthWeightsMissLinearPrecisionAndFloatersAreNotUniform) {
    const geo::Mesh sheet = jittered_sheet();
    const geo::MeshAdjacency adj = geo::build_adjacency(sheet);
    const std::vector<double> floater = gp::floater_weights(sheet, adj), chord = gp::chord_weights(sheet, adj);
    const std::vector<std::uint8_t> interior = adj.interior_vertices();
    double chord_worst = 0.0, spread = 0.0;
    for (std::size_t i = 0; i < sheet.vertex_count(); ++i) {
        if (!interior[i]) continue;
        const auto nb = adj.neighbors(i);
        glm::dvec3 mean(0.0);
        for (std::size_t k = 0; k < nb.size(); ++k) {
            mean += chord[adj.vertex_vertex_offsets[i] + k] * sheet.positions[nb[k]];
            spread = std::max(spread, std::abs(floater[adj.vertex_vertex_offsets[i] + k] - 1.0 / double(nb.size())));
        }
        chord_worst = std::max(chord_worst, glm::length(mean - sheet.positions[i]));
    }
    EXPECT_GT(chord_worst, 1e-3);  // of a spacing of 0.1
    EXPECT_GT(spread, 0.02);       // not 1 / n (the printed index swap would give that)
}

TEST_F(QuadRegion, EveryMapIsFoldFreeInsideTheSquareOnACurvedMesh) {
    GIMG_REQUIRE_SHARED_MESH(path, "bunny.off");
    const geo::Mesh bunny = geo::load_mesh(path);
    const gp::QuadRegion r = gp::cut_quad_region(bunny, kBunnyCorners);
    EXPECT_GT(r.mesh.vertex_count(), 1000u);
    for (auto weights : {gp::QuadWeights::Floater, gp::QuadWeights::Chord})
        for (auto solver : {gp::QuadSolver::Iterate, gp::QuadSolver::Krylov, gp::QuadSolver::Direct}) {
            const gp::QuadMap m = gp::map_quad_region(&ctx(), r, {.weights = weights, .solver = solver});
            EXPECT_EQ(m.flipped, 0u);
            for (const auto& p : m.uv) ASSERT_TRUE(p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1);
        }
}

TEST_F(QuadRegion, TheRelaxationsFixedPointIsTheDirectSolution) {
    GIMG_REQUIRE_SHARED_MESH(path, "bunny.off");
    const gp::QuadRegion r = gp::cut_quad_region(geo::load_mesh(path), kBunnyCorners);
    const gp::QuadMap direct = gp::map_quad_region(nullptr, r, {.solver = gp::QuadSolver::Direct});
    auto gap = [&](const gp::QuadMap& m) {
        double worst = 0.0;
        for (std::size_t i = 0; i < m.uv.size(); ++i) worst = std::max(worst, glm::length(m.uv[i] - direct.uv[i]));
        return worst;
    };
    EXPECT_LE(gap(gp::map_quad_region(nullptr, r, {.solver = gp::QuadSolver::Iterate, .tau = 1e-10})), 1e-6);
    EXPECT_LE(gap(gp::map_quad_region(&ctx(), r, {.krylov_tolerance = 1e-12})), 1e-8);
    // The paper's tau = 1e-4 tests the correction, not the error: the gap it leaves is larger.
    const double loose =
        gap(gp::map_quad_region(nullptr, r, {.start = gp::QuadStart::Flat, .solver = gp::QuadSolver::Iterate}));
    EXPECT_GT(loose, 1e-4);
    EXPECT_LT(loose, 0.1);
}

TEST(QuadStart, TheBilinearNormalisationRoundTrips) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0), scale(0.5, 2.0);
    int tried = 0;
    for (int k = 0; k < 20000; ++k) {
        const double s0 = scale(rng), t0 = scale(rng);
        const double s1 = k % 4 == 0 ? s0 : scale(rng), t1 = scale(rng);
        if (!(s1 / s0 + t1 / t0 > 1.0)) continue;
        const glm::dvec2 uv{unit(rng), unit(rng)};
        bool folded = true;
        const glm::dvec2 back = gp::bilinear_inverse(gp::bilinear_forward(uv, s0, t0, s1, t1), s0, t0, s1, t1, &folded);
        ASSERT_LE(glm::length(back - uv), 1e-12) << s0 << " " << t0 << " " << s1 << " " << t1;
        EXPECT_FALSE(folded);
        ++tried;
    }
    EXPECT_GT(tried, 10000);
    // A tapering region (s1 / s0 + t1 / t0 <= 1) folds: flagged, and the answer maps back to (s, t).
    bool folded = false;
    const glm::dvec2 st = gp::bilinear_forward({0.3, 0.6}, 1.0, 1.0, 0.3, 0.3);
    const glm::dvec2 back = gp::bilinear_inverse(st, 1.0, 1.0, 0.3, 0.3, &folded);
    EXPECT_TRUE(folded);
    EXPECT_LE(glm::length(gp::bilinear_forward(back, 1.0, 1.0, 0.3, 0.3) - st), 1e-12);
}

TEST(QuadStart, OnAStructuredRectangleTheStartIsTheAnswer) {
    geo::Mesh grid = geo::make_grid(8, 5, 2.0, 1.25);
    grid.texcoords.clear();
    const std::array<std::uint32_t, 4> corners{0, 8, 53, 45};
    const gp::QuadRegion r = gp::cut_quad_region(grid, corners);
    ASSERT_EQ(r.mesh.vertex_count(), grid.vertex_count());
    const gp::QuadMap m =
        gp::map_quad_region(nullptr, r, {.start = gp::QuadStart::Dijkstra, .solver = gp::QuadSolver::Iterate});
    for (std::size_t i = 0; i < m.start.size(); ++i) {
        EXPECT_NEAR(m.start[i].x, r.mesh.positions[i].x / 2.0, 1e-12);
        EXPECT_NEAR(m.start[i].y, r.mesh.positions[i].y / 1.25, 1e-12);
    }
    EXPECT_EQ(m.iterations_u, 1u);
    EXPECT_EQ(m.iterations_v, 1u);
    EXPECT_FALSE(m.start_folded);
}

TEST(QuadStart, SideDistancesAreNoShorterThanStraightLines) {
    // Dijkstra's s and t run along edges, so neither is below the straight distance to its side.
    GIMG_REQUIRE_SHARED_MESH(path, "bunny.off");
    const gp::QuadRegion r = gp::cut_quad_region(geo::load_mesh(path), kBunnyCorners);
    const auto [s, t] = gp::side_distances(r, geo::build_adjacency(r.mesh));
    // Side 4 (W4 -> W1) and W1 start s; side 1 (W1 -> W2) and W2 start t.
    auto straight = [&](int side, std::uint32_t end_corner, std::size_t i) {
        double d = glm::distance(r.mesh.positions[i], r.mesh.positions[end_corner]);
        for (std::size_t j = 0; j < r.mesh.vertex_count(); ++j)
            if (r.side[j] == side) d = std::min(d, glm::distance(r.mesh.positions[i], r.mesh.positions[j]));
        return d;
    };
    std::size_t longer = 0;
    for (std::size_t i = 0; i < r.mesh.vertex_count(); i += 7) {
        const double ds = straight(4, r.corners[0], i), dt = straight(1, r.corners[1], i);
        ASSERT_GE(s[i], ds - 1e-12);
        ASSERT_GE(t[i], dt - 1e-12);
        longer += s[i] > ds * (1.0 + 1e-9);
    }
    EXPECT_GT(longer, 0u);  // the edge paths bend: not the straight distance everywhere
}

TEST(QuadStart, ADartShapedRegionFoldsTheStartAndStillMaps) {
    // W3 pulled in towards W1: s1 / s0 + t1 / t0 <= 1, eq. (3) folds, the start says so, and the
    // map (a convex boundary and positive weights) is still an embedding.
    const geo::Mesh sheet = jittered_sheet();
    const gp::QuadRegion dart = gp::cut_quad_region(sheet, {nearest(sheet, {0, 0, 0}), nearest(sheet, {1, 0, 0}),
                                                            nearest(sheet, {0.3, 0.3, 0}), nearest(sheet, {0, 1, 0})});
    for (auto start : {gp::QuadStart::Dijkstra, gp::QuadStart::Overrelaxed}) {
        const gp::QuadMap m = gp::map_quad_region(nullptr, dart, {.start = start, .solver = gp::QuadSolver::Iterate});
        EXPECT_TRUE(m.start_folded);
        EXPECT_EQ(m.flipped, 0u);
        for (const auto& p : m.start) ASSERT_TRUE(p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1);
    }
    EXPECT_FALSE(gp::map_quad_region(nullptr, gp::cut_quad_region(sheet, unit_corners(sheet))).start_folded);
}

TEST(QuadStart, TheAcceleratedStartNeedsFarFewerSweeps) {
    GIMG_REQUIRE_SHARED_MESH(path, "bunny.off");
    const gp::QuadRegion r = gp::cut_quad_region(geo::load_mesh(path), kBunnyCorners);
    const gp::QuadMap flat =
        gp::map_quad_region(nullptr, r, {.start = gp::QuadStart::Flat, .solver = gp::QuadSolver::Iterate});
    const gp::QuadMap fast =
        gp::map_quad_region(nullptr, r, {.start = gp::QuadStart::Dijkstra, .solver = gp::QuadSolver::Iterate});
    EXPECT_GE(flat.iterations_u + flat.iterations_v, 3 * (fast.iterations_u + fast.iterations_v));
}

namespace {

// The over-relaxed sweeps take out the smooth error that the paper's stopping rule stops on: the
// relaxation after them needs a few sweeps, and its map lies closer to the exact one.
void expect_overrelaxed_start_finishes_closer(const gp::QuadRegion& r, std::size_t most_sweeps) {
    const gp::QuadMap direct = gp::map_quad_region(nullptr, r, {.solver = gp::QuadSolver::Direct});
    auto gap = [&](const gp::QuadMap& m) {
        double worst = 0.0;
        for (std::size_t i = 0; i < m.uv.size(); ++i) worst = std::max(worst, glm::length(m.uv[i] - direct.uv[i]));
        return worst;
    };
    const gp::QuadMap paper =
        gp::map_quad_region(nullptr, r, {.start = gp::QuadStart::Dijkstra, .solver = gp::QuadSolver::Iterate});
    const gp::QuadMap over =
        gp::map_quad_region(nullptr, r, {.start = gp::QuadStart::Overrelaxed, .solver = gp::QuadSolver::Iterate});
    EXPECT_EQ(over.overrelaxed_sweeps, gp::kOverrelaxedSweeps);
    EXPECT_EQ(paper.overrelaxed_sweeps, 0u);
    EXPECT_LE(std::max(over.iterations_u, over.iterations_v), most_sweeps);
    EXPECT_GE(paper.iterations_u + paper.iterations_v, 4 * (over.iterations_u + over.iterations_v));
    EXPECT_LT(gap(over), gap(paper));
    EXPECT_EQ(over.flipped, 0u);
}

}  // namespace

TEST(QuadStart, TheOverrelaxedStartFinishesInAFewSweepsAndCloser) {
    // A curved, jittered sheet of 40 x 40 squares, the unit square cut from its middle.
    geo::Mesh sheet = jittered_sheet(40, 0.015, 11);
    for (auto& p : sheet.positions) p.z = 0.3 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y);
    expect_overrelaxed_start_finishes_closer(gp::cut_quad_region(sheet, unit_corners(sheet)), 8);
}

TEST(QuadStart, TheOverrelaxedStartFinishesInAFewSweepsAndCloserOnBunny) {
    GIMG_REQUIRE_SHARED_MESH(path, "bunny.off");
    expect_overrelaxed_start_finishes_closer(gp::cut_quad_region(geo::load_mesh(path), kBunnyCorners), 8);
}

TEST(QuadRegionCut, SidesLieOnTheirPlanesAndCloseOneLoop) {
    GIMG_REQUIRE_SHARED_MESH(path, "bunny.off");
    const geo::Mesh bunny = geo::load_mesh(path);
    const gp::QuadRegion r = gp::cut_quad_region(bunny, kBunnyCorners);
    const std::vector<glm::dvec3> fn = geo::face_normals(bunny);
    const geo::MeshAdjacency adj = geo::build_adjacency(bunny);
    std::array<glm::dvec3, 4> n{};
    for (int i = 0; i < 4; ++i) {
        for (std::uint32_t f : adj.faces_of_vertex(kBunnyCorners[i])) n[i] += fn[f];
        n[i] = glm::normalize(n[i]);
    }
    const double diagonal = bunny.bounds().diagonal();
    std::size_t checked = 0;
    for (std::size_t v = 0; v < r.mesh.vertex_count(); ++v) {
        if (r.original[v] != gp::kInsertedNode) continue;
        const int i = r.side[v] - 1;
        ASSERT_GE(i, 0);
        const glm::dvec3 w = bunny.positions[kBunnyCorners[i]], w1 = bunny.positions[kBunnyCorners[(i + 1) % 4]];
        const glm::dvec3 plane = glm::normalize(glm::cross(w - w1, n[i] + n[(i + 1) % 4]));
        EXPECT_LT(std::abs(glm::dot(plane, r.mesh.positions[v] - w)), 1e-9 * diagonal);
        ++checked;
    }
    EXPECT_EQ(checked, r.inserted);
    for (const auto& t : r.mesh.triangles)
        for (int k = 0; k < 3; ++k)
            EXPECT_GT(glm::distance(r.mesh.positions[t[k]], r.mesh.positions[t[(k + 1) % 3]]), 0.0);
    EXPECT_NO_THROW(gp::check_disk_mesh(r.mesh));  // one boundary loop: the four sides
}

TEST(QuadRegionCut, RefusesCornersThatSpanNoRegion) {
    const geo::Mesh sheet = jittered_sheet();
    auto c = unit_corners(sheet);
    EXPECT_THROW(gp::cut_quad_region(sheet, {c[0], c[1], c[1], c[3]}), geo::InputError);
    EXPECT_THROW(gp::cut_quad_region(sheet, {c[0], c[1], c[2], 100000}), geo::InputError);
    // Clockwise: the faces on the left are the rest of the sheet, which reaches its boundary.
    EXPECT_THROW(gp::cut_quad_region(sheet, {c[0], c[3], c[2], c[1]}), geo::InputError);
    // A hole inside the square: the region has two boundary loops, not a disk.
    geo::Mesh holed = sheet;
    holed.triangles.erase(
        std::remove_if(holed.triangles.begin(), holed.triangles.end(),
                       [&](const glm::uvec3& t) {
                           const glm::dvec3 m =
                               (holed.positions[t[0]] + holed.positions[t[1]] + holed.positions[t[2]]) / 3.0;
                           return glm::distance(m, glm::dvec3(0.5, 0.5, 0.0)) < 0.15;
                       }),
        holed.triangles.end());
    try {
        (void)gp::cut_quad_region(holed, unit_corners(holed));
        ADD_FAILURE() << "a region with a hole was cut";
    } catch (const geo::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("not a disk"), std::string::npos) << e.what();
    }
    // The same square without the hole is a disk of V - E + F = 1.
    const gp::QuadRegion whole = gp::cut_quad_region(sheet, c);
    const geo::MeshInfo info = geo::analyze_topology(whole.mesh);
    EXPECT_EQ(info.boundary_loops, 1u);
    EXPECT_TRUE(info.manifold);
}

TEST(QuadDeform, TheLatticeVanishesToSecondOrderAtTheBoundaryWithTwoFixedLayers) {
    gp::OffsetLattice lattice{.columns = 9, .rows = 9};
    lattice.offsets.assign(81, glm::dvec3(0.0, 0.0, 1.0));
    // Partition of unity, every control point counted.
    lattice.fixed_layers = -1;
    for (double u : {0.0, 0.17, 0.5, 0.93, 1.0}) EXPECT_NEAR(lattice.evaluate({u, 0.4}).z, 1.0, 1e-12);
    // F'' at the boundary by finite differences: zero with L = 2, not with L = 1.
    auto second = [&](int layers, double h) {
        lattice.fixed_layers = layers;
        return (lattice.evaluate({2 * h, 0.5}).z - 2 * lattice.evaluate({h, 0.5}).z + lattice.evaluate({0.0, 0.5}).z) /
               (h * h);
    };
    // With L = 2 the difference quotient shrinks with h (F ~ h^3); with L = 1 it tends to F''(0) != 0.
    EXPECT_LT(std::abs(second(2, 1e-4)), 0.1 * std::abs(second(2, 1e-2)));
    EXPECT_LT(std::abs(second(2, 1e-4)), 0.05);
    EXPECT_GT(std::abs(second(1, 1e-4)), 10.0);
    EXPECT_NEAR(second(1, 1e-4), second(1, 1e-3), 0.01 * std::abs(second(1, 1e-4)) + 0.5);
    lattice.fixed_layers = 2;
    for (double t : {0.0, 0.3, 1.0}) {
        EXPECT_EQ(lattice.evaluate({0.0, t}), glm::dvec3(0.0));
        EXPECT_EQ(lattice.evaluate({1.0, t}), glm::dvec3(0.0));
        EXPECT_EQ(lattice.evaluate({t, 1.0}), glm::dvec3(0.0));
    }
}

TEST(QuadDeform, ZeroChangesNothingAndPastingMovesAlongTheNormal) {
    const geo::Mesh sheet = jittered_sheet();
    const gp::QuadRegion r = gp::cut_quad_region(sheet, unit_corners(sheet));
    const gp::QuadMap m = gp::map_quad_region(nullptr, r, {.solver = gp::QuadSolver::Direct});
    gp::OffsetLattice zero;
    zero.offsets.assign(64, glm::dvec3(0.0));
    EXPECT_EQ(gp::deform_by_lattice(sheet, r, m.uv, zero).positions, sheet.positions);
    EXPECT_EQ(gp::paste_feature(sheet, r, m.uv, {.scale = 0.0}).positions, sheet.positions);
    const gp::PastedFeature bump{.scale = 0.1};
    const geo::Mesh pasted = gp::paste_feature(sheet, r, m.uv, bump);
    const double diagonal = sheet.bounds().diagonal();
    for (std::size_t i = 0; i < m.uv.size(); ++i) {
        if (r.original[i] == gp::kInsertedNode) continue;
        const glm::dvec3 d = pasted.positions[r.original[i]] - sheet.positions[r.original[i]];
        EXPECT_NEAR(d.z, bump.evaluate(m.uv[i]) * diagonal, 1e-12);  // the sheet's normal is +z
        EXPECT_EQ(d.x, 0.0);
        if (r.side[i]) {
            EXPECT_EQ(d.z, 0.0);  // the boundary stays
        }
    }
}

TEST_F(QuadRegion, TheRelaxationOnTheGpuIsItsCpuTwin) {
    // Gauss-Seidel in colour order: one workgroup per field sweeping colour after colour on the
    // GPU, the same rows in the same order on the CPU; the same sweep counts and the same map. The
    // finer sheet has more rows per colour than the workgroup has invocations.
    for (const int squares : {20, 80}) {
        geo::Mesh sheet = jittered_sheet(squares, 0.6 / squares);  // jitter 0.3 of a square, as the default

        for (auto& p : sheet.positions) p.z = 0.2 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y);  // curved
        const gp::QuadRegion r = gp::cut_quad_region(sheet, unit_corners(sheet));
        if (squares == 80) {
            EXPECT_GT(r.mesh.vertex_count(), 6u * GIMG_RELAX_GROUP);  // a sheet colours in at most 6 or so
        }
        for (auto start : {gp::QuadStart::Flat, gp::QuadStart::Dijkstra, gp::QuadStart::Overrelaxed}) {
            const gp::QuadMapOptions o{.start = start, .solver = gp::QuadSolver::Iterate};
            const gp::QuadMap gpu = gp::map_quad_region(&ctx(), r, o), cpu = gp::map_quad_region(nullptr, r, o);
            EXPECT_EQ(gpu.iterations_u, cpu.iterations_u);
            EXPECT_EQ(gpu.iterations_v, cpu.iterations_v);
            EXPECT_EQ(gpu.overrelaxed_sweeps, cpu.overrelaxed_sweeps);
            // The over-relaxed sweeps (no stopping rule) are the work there, and the starts must agree.
            if (start == gp::QuadStart::Overrelaxed)
                EXPECT_EQ(cpu.overrelaxed_sweeps, gp::kOverrelaxedSweeps);
            else
                EXPECT_GT(cpu.iterations_u, 1u);
            double worst = 0.0;
            for (std::size_t i = 0; i < cpu.uv.size(); ++i)
                worst = std::max({worst, glm::length(gpu.uv[i] - cpu.uv[i]), glm::length(gpu.start[i] - cpu.start[i])});
            EXPECT_LE(worst, 1e-12);
            EXPECT_EQ(gpu.flipped, 0u);
        }
    }
}

TEST_F(QuadRegion, ARelaxationThatDoesNotSettleIsRefusedOnBothPaths) {
    const geo::Mesh sheet = jittered_sheet();
    const gp::QuadRegion r = gp::cut_quad_region(sheet, unit_corners(sheet));
    // From the flat start the relaxation needs far more than 20 sweeps to reach tau = 1e-4.
    const gp::QuadMapOptions o{.start = gp::QuadStart::Flat, .solver = gp::QuadSolver::Iterate, .max_sweeps = 20};
    for (Context* c : {static_cast<Context*>(nullptr), &ctx()}) {
        try {
            gp::map_quad_region(c, r, o);
            ADD_FAILURE() << (c ? "gpu" : "cpu") << ": no error";
        } catch (const geo::InputError& e) {
            EXPECT_NE(std::string(e.what()).find("did not settle within 20 sweeps"), std::string::npos) << e.what();
        }
    }
}

TEST_F(QuadRegion, TheDeformationPassIsItsCpuTwin) {
    geo::Mesh sheet = jittered_sheet();
    for (auto& p : sheet.positions) p.z = 0.2 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y);
    const gp::QuadRegion r = gp::cut_quad_region(sheet, unit_corners(sheet));
    const gp::QuadMap m = gp::map_quad_region(nullptr, r, {.solver = gp::QuadSolver::Direct});
    auto worst = [](const geo::Mesh& a, const geo::Mesh& b) {
        double w = 0.0;
        for (std::size_t i = 0; i < a.positions.size(); ++i)
            w = std::max(w, glm::distance(a.positions[i], b.positions[i]));
        return w;
    };
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> offset(-0.1, 0.1);
    gp::OffsetLattice lattice{.columns = 11, .rows = 9};
    for (int k = 0; k < 99; ++k) lattice.offsets.push_back({offset(rng), offset(rng), offset(rng)});
    const geo::Mesh cpu = gp::deform_by_lattice(sheet, r, m.uv, lattice);
    EXPECT_GT(worst(cpu, sheet), 1e-3);  // it moved
    EXPECT_LE(worst(gp::deform_by_lattice_gpu(ctx(), sheet, r, m.uv, lattice), cpu), 1e-13);
    const gp::PastedFeature bump{.scale = 0.05};
    EXPECT_LE(worst(gp::paste_feature_gpu(ctx(), sheet, r, m.uv, bump), gp::paste_feature(sheet, r, m.uv, bump)),
              1e-13);
    gp::PastedFeature map{.width = 5, .height = 4, .scale = 0.02};
    for (int k = 0; k < 20; ++k) map.heights.push_back(float(offset(rng)));
    const geo::Mesh pasted = gp::paste_feature(sheet, r, m.uv, map);
    EXPECT_GT(worst(pasted, sheet), 1e-5);
    EXPECT_LE(worst(gp::paste_feature_gpu(ctx(), sheet, r, m.uv, map), pasted), 1e-13);
}

namespace {

gp::OffsetLattice random_lattice(std::uint32_t columns, std::uint32_t rows, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> offset(-0.1, 0.1);
    gp::OffsetLattice lattice{.columns = columns, .rows = rows};
    for (std::uint32_t k = 0; k < columns * rows; ++k)
        lattice.offsets.push_back({offset(rng), offset(rng), offset(rng)});
    return lattice;
}

geo::Mesh curved_sheet() {
    geo::Mesh sheet = jittered_sheet();
    for (auto& p : sheet.positions) p.z = 0.2 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y);
    return sheet;
}

}  // namespace

TEST(QuadRegionEditor, AnOffsetEditGivesTheDeformationOfItsMap) {
    // The editor keeps the basis values at its map's points; its result must be deform_by_lattice's.
    const geo::Mesh sheet = curved_sheet();
    gp::QuadRegionEditor editor(nullptr, sheet, unit_corners(sheet), {.solver = gp::QuadSolver::Iterate});
    for (const auto& [columns, rows, seed] : {std::tuple{8u, 8u, 1u}, {8u, 8u, 2u}, {11u, 9u, 3u}, {4u, 6u, 4u}}) {
        const gp::OffsetLattice lattice = random_lattice(columns, rows, seed);
        const std::vector<glm::dvec3> edited = editor.set_lattice(lattice).positions;
        const geo::Mesh fresh = gp::deform_by_lattice(sheet, editor.region(), editor.map().uv, lattice);
        EXPECT_EQ(edited, fresh.positions) << columns << " x " << rows;
        EXPECT_EQ(editor.deformed().triangles, sheet.triangles);
        if (columns > 4) {
            EXPECT_NE(edited, sheet.positions);  // it moved (a 4-wide lattice has no free control point)
        }
    }
    // A lattice that does not fit is refused and the editor keeps its last result.
    const std::vector<glm::dvec3> before = editor.deformed().positions;
    gp::OffsetLattice bad = random_lattice(8, 8, 5);
    bad.offsets.pop_back();
    EXPECT_THROW(editor.set_lattice(bad), geo::InputError);
    EXPECT_EQ(editor.deformed().positions, before);
}

TEST(QuadRegionEditor, AMovedCornerIsMappedAgainFromTheLastMap) {
    const geo::Mesh sheet = curved_sheet();
    const std::array<std::uint32_t, 4> corners = unit_corners(sheet);
    const gp::QuadMapOptions options{.solver = gp::QuadSolver::Iterate};
    gp::QuadRegionEditor editor(nullptr, sheet, corners, options);
    const gp::OffsetLattice lattice = random_lattice(8, 8, 6);
    editor.set_lattice(lattice);
    // Corner 2, (1, 1), one vertex up: the region, the map and the deformation follow it.
    const std::uint32_t moved = nearest(sheet, sheet.positions[corners[2]] + glm::dvec3(0.0, 0.1, 0.0));
    ASSERT_NE(moved, corners[2]);
    const std::array<std::uint32_t, 4> next{corners[0], corners[1], moved, corners[3]};
    const geo::Mesh& deformed = editor.move_corner(2, moved);
    const gp::QuadRegion region = gp::cut_quad_region(sheet, next);
    ASSERT_EQ(editor.region().mesh.vertex_count(), region.mesh.vertex_count());
    EXPECT_EQ(editor.region().original, region.original);
    const gp::QuadMap exact = gp::map_quad_region(nullptr, region, {.solver = gp::QuadSolver::Direct});
    double gap = 0.0;
    for (std::size_t i = 0; i < exact.uv.size(); ++i)
        gap = std::max(gap, glm::length(editor.map().uv[i] - exact.uv[i]));
    EXPECT_LT(gap, 0.01);  // within what the paper's tau allows
    EXPECT_EQ(editor.map().flipped, 0u);
    EXPECT_EQ(deformed.positions, gp::deform_by_lattice(sheet, region, editor.map().uv, lattice).positions);
    // A corner that spans no region is refused and the editor stays as it was.
    const std::size_t vertices = editor.region().mesh.vertex_count();
    const std::vector<glm::dvec3> before = editor.deformed().positions;
    EXPECT_THROW(editor.move_corner(1, corners[0]), geo::InputError);
    EXPECT_EQ(editor.region().mesh.vertex_count(), vertices);
    EXPECT_EQ(editor.deformed().positions, before);
    EXPECT_THROW(editor.move_corner(4, moved), geo::InputError);
}

TEST(QuadRegionEditor, StartingFromTheLastMapSavesSweepsOnBunny) {
    // The paper's start, each corner in turn moved to a neighbour: the last map's correction to its
    // own accelerated start, added to the new region's, leaves the relaxation less to do than the
    // new accelerated start alone. (The last map itself as the start does worse than that on this
    // region: the moved corner shifts the whole square.)
    GIMG_REQUIRE_SHARED_MESH(path, "bunny.off");
    const geo::Mesh bunny = geo::load_mesh(path);
    const geo::MeshAdjacency adj = geo::build_adjacency(bunny);
    const gp::QuadMapOptions options{.start = gp::QuadStart::Dijkstra, .solver = gp::QuadSolver::Iterate};
    std::size_t warm = 0, cold = 0;
    for (int c = 0; c < 4; ++c) {
        gp::QuadRegionEditor editor(nullptr, bunny, kBunnyCorners, options);
        std::array<std::uint32_t, 4> next = kBunnyCorners;
        next[std::size_t(c)] = adj.neighbors(kBunnyCorners[std::size_t(c)]).front();
        editor.move_corner(c, next[std::size_t(c)]);
        const gp::QuadMap fresh = gp::map_quad_region(nullptr, gp::cut_quad_region(bunny, next), options);
        EXPECT_EQ(editor.map().flipped, 0u);
        EXPECT_LT(editor.map().iterations_u + editor.map().iterations_v, fresh.iterations_u + fresh.iterations_v);
        warm += editor.map().iterations_u + editor.map().iterations_v;
        cold += fresh.iterations_u + fresh.iterations_v;
    }
    EXPECT_LT(2 * warm, cold);
}

TEST(QuadDeform, PolarCoordinatesAndTheConcentricLattice) {
    const glm::dvec2 east = gp::polar_coordinates({1.0, 0.5}), north = gp::polar_coordinates({0.5, 1.0});
    EXPECT_NEAR(east.x, 1.0, 1e-15);
    EXPECT_NEAR(east.y, 0.0, 1e-15);
    EXPECT_NEAR(north.x, 1.0, 1e-15);
    EXPECT_NEAR(north.y, std::numbers::pi / 2, 1e-15);
    const glm::dvec2 p = gp::polar_coordinates({0.3, 0.2});  // round trip
    EXPECT_NEAR(0.5 + 0.5 * p.x * std::cos(p.y), 0.3, 1e-15);
    EXPECT_NEAR(0.5 + 0.5 * p.x * std::sin(p.y), 0.2, 1e-15);
    gp::PolarLattice lattice{.rings = 9, .sectors = 6};
    for (std::uint32_t k = 0; k < 54; ++k) lattice.offsets.push_back({0.0, 0.0, 1.0 + double(k % 6)});
    EXPECT_EQ(lattice.evaluate({0.5, 0.5}), glm::dvec3(0.0));    // the centre
    EXPECT_EQ(lattice.evaluate({1.0, 0.5}), glm::dvec3(0.0));    // the inscribed circle
    EXPECT_EQ(lattice.evaluate({0.99, 0.99}), glm::dvec3(0.0));  // beyond it
    auto at = [&](double r, double theta) {
        return lattice.evaluate({0.5 + 0.5 * r * std::cos(theta), 0.5 + 0.5 * r * std::sin(theta)}).z;
    };
    EXPECT_GT(at(0.5, 0.3), 0.1);
    EXPECT_GT(std::abs(at(0.5, 0.3) - at(0.5, 2.3)), 0.1);                   // it turns with theta
    EXPECT_NEAR(at(0.5, 1e-9), at(0.5, 2 * std::numbers::pi - 1e-9), 1e-6);  // and closes around
    EXPECT_LT(std::abs(at(0.98, 1.0)), 1e-3);                                // fading to the circle
}

TEST_F(QuadRegion, APlanarTriangleGetsItsBarycentricCoordinates) {
    // A triangle meshed irregularly (rows of points, interior ones jittered), corners at its corners.
    const int n = 12;
    geo::Mesh tri;
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    const glm::dvec3 a{0, 0, 0}, b{1, 0, 0}, c{0.3, 0.9, 0};
    std::vector<std::vector<std::uint32_t>> id(n + 1);
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n - i; ++j) {
            glm::dvec3 p = a + (b - a) * (double(j) / n) + (c - a) * (double(i) / n);
            if (i > 0 && j > 0 && i + j < n) p += glm::dvec3(jitter(rng), jitter(rng), 0.0);
            id[i].push_back(std::uint32_t(tri.positions.size()));
            tri.positions.push_back(p);
        }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n - i; ++j) {
            tri.triangles.push_back({id[i][j], id[i][j + 1], id[i + 1][j]});
            if (j + 1 < n - i) tri.triangles.push_back({id[i][j + 1], id[i + 1][j + 1], id[i + 1][j]});
        }
    const gp::QuadRegion r = gp::cut_triangle_region(tri, {id[0][0], id[0][n], id[n][0]});
    ASSERT_EQ(r.corner_count, 3u);
    ASSERT_EQ(r.mesh.vertex_count(), tri.vertex_count());
    auto truth = [&](glm::dvec3 p) {
        // Solve p = a + s (b - a) + t (c - a) in the plane.
        const glm::dvec2 e1{b.x - a.x, b.y - a.y}, e2{c.x - a.x, c.y - a.y}, q{p.x - a.x, p.y - a.y};
        const double det = e1.x * e2.y - e1.y * e2.x;
        const double s = (q.x * e2.y - q.y * e2.x) / det, t = (e1.x * q.y - e1.y * q.x) / det;
        return glm::dvec3(1.0 - s - t, s, t);
    };
    for (Context* c2 : {static_cast<Context*>(nullptr), &ctx()}) {
        const std::vector<glm::dvec3> bary = gp::barycentric_map(c2, r);
        double worst = 0.0;
        for (std::size_t i = 0; i < bary.size(); ++i) {
            worst = std::max(worst, glm::length(bary[i] - truth(r.mesh.positions[i])));
            EXPECT_NEAR(bary[i].x + bary[i].y + bary[i].z, 1.0, 1e-14);
        }
        EXPECT_LE(worst, c2 ? 1e-9 : 1e-12) << (c2 ? "gpu" : "cpu");
    }
    EXPECT_THROW(gp::map_quad_region(nullptr, r), geo::InputError);
}

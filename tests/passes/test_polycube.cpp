// Polycubes and polycube maps (spec sec. 3.7): saddle counts 2g, plane spacing, closed contours on
// closed meshes, the Bezier and fallback closures against their worked values, the quadtree stop
// rule and its monotonicity, the polyhedron (closed, manifold, axis-aligned, chi = 2 - 2g), a box
// giving one box, open cylinders giving holes, and the map (no flipped triangle, the same image of a
// contour from both sides, every image on the polycube), on the GPU against the CPU twins.
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/polycube.h"
#include "polycube/polycube_parts.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>

using namespace gimg;
namespace gp = gimg::passes;

namespace {

class PolycubeGpu : public gimg::test::GpuTest {};

long long euler(const geo::Mesh& m) {
    long long chi = 0;
    for (const auto& c : geo::analyze_topology(m).component_info) chi += c.euler_characteristic;
    return chi;
}

// An upright tube (axis z) of radius 1 and height 2, open at both ends: `around` x `rows` quads;
// `side_hole` removes a block of quads on the +x side, half way up.
geo::Mesh open_cylinder(int around, int rows, bool side_hole) {
    geo::Mesh m;
    for (int r = 0; r <= rows; ++r)
        for (int a = 0; a < around; ++a) {
            const double t = 2.0 * std::numbers::pi * a / around;
            m.positions.push_back({std::cos(t), std::sin(t), -1.0 + 2.0 * r / rows});
        }
    for (int r = 0; r < rows; ++r)
        for (int a = 0; a < around; ++a) {
            if (side_hole && r >= rows / 2 - 2 && r < rows / 2 + 2 && (a <= 2 || a >= around - 2)) continue;
            const std::uint32_t v00 = r * around + a, v01 = r * around + (a + 1) % around, v10 = (r + 1) * around + a,
                                v11 = (r + 1) * around + (a + 1) % around;
            m.triangles.push_back({v00, v01, v11});
            m.triangles.push_back({v00, v11, v10});
        }
    return m;
}

void expect_valid_polycube(const gp::Polycube& p, long long genus) {
    EXPECT_TRUE(p.stats.polycube_valid) << p.stats.invalid_reason;
    const geo::MeshInfo info = geo::analyze_topology(p.surface);
    EXPECT_TRUE(info.closed);
    EXPECT_TRUE(info.manifold);
    EXPECT_TRUE(info.oriented);
    EXPECT_EQ(info.components, 1u);
    EXPECT_EQ(euler(p.surface), 2 - 2 * genus);
    // Every triangle lies in a plane normal to one axis, and faces the way its axis says.
    for (std::size_t f = 0; f < p.surface.face_count(); ++f) {
        const auto& t = p.surface.triangles[f];
        const glm::dvec3 n = glm::cross(p.surface.positions[t[1]] - p.surface.positions[t[0]],
                                        p.surface.positions[t[2]] - p.surface.positions[t[0]]);
        ASSERT_GT(glm::length(n), 0.0);
        const glm::dvec3 u = glm::normalize(n);
        ASSERT_NEAR(std::max({std::abs(u.x), std::abs(u.y), std::abs(u.z)}), 1.0, 1e-12) << "triangle " << f;
        ASSERT_EQ(gp::axis_of(u), p.face_axis[f]);
    }
}

}  // namespace

TEST(PolycubeCriticalStructure, SaddlesCountTwiceTheGenus) {
    const gp::CriticalStructure sphere = gp::critical_structure(nullptr, geo::make_icosphere(1.0, 3));
    EXPECT_EQ(sphere.saddle_count(), 0u);
    EXPECT_EQ(sphere.extrema, 2u);
    // A torus standing in the xz plane (its axis y): two saddles against the height z.
    const gp::CriticalStructure torus = gp::critical_structure(nullptr, geo::make_torus(1.0, 0.35, 48, 16));
    EXPECT_EQ(torus.saddle_count(), 2u);
    EXPECT_EQ(torus.extrema, 2u);
    EXPECT_TRUE(torus.converged);
    EXPECT_DOUBLE_EQ(torus.f[torus.minimum], 0.0);
    EXPECT_DOUBLE_EQ(torus.f[torus.maximum], 1.0);
    for (double v : torus.f) EXPECT_TRUE(v >= -1e-9 && v <= 1.0 + 1e-9);  // the maximum principle
}

TEST(PolycubeCriticalStructure, DoubleTorusHasFourSaddles) {
    GIMG_REQUIRE_SHARED_MESH(path, "eight.off");
    const gp::CriticalStructure cs = gp::critical_structure(nullptr, geo::load_mesh(path));
    EXPECT_EQ(cs.saddle_count(), 4u);
    EXPECT_EQ(cs.extrema, 2u);
}

TEST_F(PolycubeGpu, HarmonicFunctionMatchesTheCpuTwin) {
    const geo::Mesh torus = geo::make_torus(1.0, 0.35, 48, 16);
    const gp::CriticalStructure gpu = gp::critical_structure(&ctx(), torus);
    const gp::CriticalStructure cpu = gp::critical_structure(nullptr, torus);
    ASSERT_EQ(gpu.f.size(), cpu.f.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < gpu.f.size(); ++i) worst = std::max(worst, std::abs(gpu.f[i] - cpu.f[i]));
    EXPECT_LT(worst, 1e-6);
    EXPECT_EQ(gpu.saddle_count(), cpu.saddle_count());
}

TEST(PolycubePlanes, MidpointsThenEveryGapBelowDz) {
    // Minimum, four saddles, maximum: 2g + 1 = 5 midpoint planes, nothing inserted with a wide dz.
    auto planes = gp::cutting_planes({0.0, 1.0, 2.0, 3.0, 4.0, 5.0}, 100.0, 1e-3);
    ASSERT_EQ(planes.size(), 5u);
    for (std::size_t i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(planes[i].z, 0.5 + double(i));
    // dz = 3 over [0, 10]: the midpoint 5, then floor(5 / 3) = 1 plane in each end gap.
    planes = gp::cutting_planes({10.0, 0.0}, 3.0, 1e-3);
    ASSERT_EQ(planes.size(), 3u);
    EXPECT_DOUBLE_EQ(planes[0].z, 2.5);
    EXPECT_DOUBLE_EQ(planes[1].z, 5.0);
    EXPECT_DOUBLE_EQ(planes[2].z, 7.5);
    EXPECT_TRUE(planes[0].inserted && !planes[1].inserted && planes[2].inserted);
    // A gap of 7 with dz = 2: floor(7 / 2) = 3 planes, evenly, every gap below dz.
    planes = gp::cutting_planes({0.0, 7.0, 14.0}, 2.0, 1e-3);
    std::vector<double> z{0.0};
    for (const auto& p : planes) z.push_back(p.z);
    z.push_back(14.0);
    for (std::size_t i = 0; i + 1 < z.size(); ++i) EXPECT_LT(z[i + 1] - z[i], 2.0);
    // Critical heights closer than the merge tolerance give one plane between them and the next.
    planes = gp::cutting_planes({0.0, 0.0005, 1.0}, 100.0, 1e-3);
    ASSERT_EQ(planes.size(), 1u);
    EXPECT_DOUBLE_EQ(planes[0].z, 0.5);
}

TEST(PolycubeContours, ClosedMeshesGiveClosedSimpleContours) {
    const geo::Mesh torus = geo::make_torus(1.0, 0.35, 48, 16);
    const std::vector<double> z{-1.1037, -0.4913, 0.0131, 0.7717};  // clear of the vertices' heights
    const gp::polycube::SlicedMesh sliced = gp::polycube::slice_mesh(torus, z);
    const auto contours = gp::polycube::plane_contours(sliced, z.size(), torus.face_count());
    std::vector<std::size_t> per_plane(z.size(), 0);
    for (const auto& c : contours) {
        ++per_plane[c.plane];
        for (std::uint8_t g : c.gap) EXPECT_EQ(g, 0);  // no cap, no gap
        for (std::uint32_t v : c.vertices) EXPECT_EQ(sliced.mesh.positions[v].z, z[c.plane]);
        const std::size_t n = c.vertices.size();
        const auto p = [&](std::size_t i) {
            const glm::dvec3 q = sliced.mesh.positions[c.vertices[i % n]];
            return glm::dvec2(q.x, q.y);
        };
        for (std::size_t i = 0; i < n; ++i)  // simple: no two non-adjacent segments meet
            for (std::size_t j = i + 2; j < n; ++j)
                if (!(i == 0 && j == n - 1)) {
                    ASSERT_FALSE(gp::polycube::segments_cross(p(i), p(i + 1), p(j), p(j + 1)));
                }
    }
    // A plane through the hole (|z| < R - r = 0.65) cuts the ring in two loops, one beyond it in one.
    EXPECT_EQ(per_plane[0], 1u);
    EXPECT_EQ(per_plane[1], 2u);
    EXPECT_EQ(per_plane[2], 2u);
    EXPECT_EQ(per_plane[3], 1u);
}

TEST(PolycubeClosure, BezierOfThreeQuartersOfACircle) {
    // The chain runs counter-clockwise from (0, 1) round to (1, 0); its end edges extended meet at (1, 1).
    const glm::dvec2 r0(1.0, 0.0), r1(0.0, 1.0), d0(0.0, 1.0), d1(1.0, 0.0);
    ASSERT_TRUE(gp::ray_intersection(r0, d0, r1, d1).has_value());
    EXPECT_NEAR(glm::length(*gp::ray_intersection(r0, d0, r1, d1) - glm::dvec2(1.0, 1.0)), 0.0, 1e-15);
    const auto curve = gp::bezier_closure(r0, d0, r1, d1, 64);
    ASSERT_EQ(curve.size(), 65u);
    EXPECT_NEAR(curve[32].x, 0.6875, 1e-15);
    EXPECT_NEAR(curve[32].y, 0.6875, 1e-15);
    EXPECT_NEAR(glm::length(curve[32]), 0.97227, 1e-5);
    double deviation = 0.0;
    for (const auto& p : curve) {
        deviation = std::max(deviation, std::abs(glm::length(p) - 1.0));
        EXPECT_GE(p.x, -1e-15);  // inside the triangle r0, (1, 1), r1
        EXPECT_GE(p.y, -1e-15);
        EXPECT_LE(p.x, 1.0 + 1e-15);
        EXPECT_LE(p.y, 1.0 + 1e-15);
        EXPECT_GE(p.x + p.y, 1.0 - 1e-15);
    }
    EXPECT_NEAR(deviation, 0.02773, 1e-4);
    // Tangent to the chain at both ends: the first and last chords turn towards the rays as the
    // sampling refines (B'(0) = 3 (m0 - r0) is along d0).
    const auto fine = gp::bezier_closure(r0, d0, r1, d1, 4096);
    const glm::dvec2 t0 = glm::normalize(fine[1] - fine[0]), t1 = glm::normalize(fine[4095] - fine[4096]);
    EXPECT_LT(std::abs(t0.x), 1e-3);
    EXPECT_GT(t0.y, 0.0);
    EXPECT_LT(std::abs(t1.y), 1e-3);
    EXPECT_GT(t1.x, 0.0);
    // Rays that never meet give no Bezier (the fallback's case).
    EXPECT_FALSE(gp::ray_intersection(r0, {1.0, 0.0}, r1, {1.0, 0.0}).has_value());
    EXPECT_TRUE(gp::bezier_closure(r0, {1.0, 0.0}, r1, {-1.0, 0.0}, 8).empty());
}

TEST(PolycubeClosure, FallbackWorkedExample) {
    const double s = 1.0 / std::sqrt(2.0);
    const auto p = gp::fallback_closure({-1.0, 0.0}, {s, -s}, {1.0, 0.0}, {-s, -s}, 2);
    const std::vector<glm::dvec2> expected{{-1.0, 0.0},
                                           {-2.0 / 3.0, -1.0 / 6.0},
                                           {-1.0 / 6.0, -1.0 / 6.0},
                                           {1.0 / 6.0, -1.0 / 6.0},
                                           {2.0 / 3.0, -1.0 / 6.0},
                                           {1.0, 0.0}};
    ASSERT_EQ(p.size(), expected.size());  // 2k + 2
    for (std::size_t i = 0; i < p.size(); ++i) EXPECT_NEAR(glm::length(p[i] - expected[i]), 0.0, 1e-12) << i;
    EXPECT_EQ(gp::fallback_closure({-1.0, 0.0}, {s, -s}, {1.0, 0.0}, {-s, -s}, 5).size(), 12u);
}

TEST(PolycubeQuadtree, RectangleIsItsOwnRootAtDepthZero) {
    const std::vector<std::vector<glm::dvec2>> rect{{{0, 0}, {3, 0}, {3, 1}, {0, 1}}};
    const auto r = gp::rectilinear_region(rect, {{0, 0}, {3, 1}}, 0.05, 8);
    EXPECT_EQ(r.depth, 0u);
    ASSERT_EQ(r.cells.size(), 1u);
    EXPECT_EQ(r.cells[0], 1);
    EXPECT_NEAR(r.excess(), 0.0, 1e-12);
    EXPECT_TRUE(r.topology_ok);
}

TEST(PolycubeQuadtree, StopRuleAndMonotoneInDa) {
    std::vector<glm::dvec2> circle;
    for (int i = 0; i < 200; ++i) {
        const double t = 2.0 * std::numbers::pi * i / 200;
        circle.push_back({0.3 * std::cos(t), 0.3 * std::sin(t)});
    }
    const gp::Rect root{{-1, -1}, {1, 1}};
    std::uint32_t last_depth = 0;
    double last_excess = 1e300;
    for (double da : {2.0, 0.5, 0.2, 0.1, 0.05, 0.02}) {
        const auto r = gp::rectilinear_region({circle}, root, da, 9);
        EXPECT_TRUE(r.excess() < da || r.depth == 9u) << da;
        EXPECT_GE(r.excess(), 0.0);  // p holds the region
        EXPECT_GE(r.depth, last_depth);
        EXPECT_LE(r.excess(), last_excess + 1e-15);
        last_depth = r.depth;
        last_excess = r.excess();
        // Every cell centre inside the circle is in p.
        const int n = 1 << r.depth;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::dvec2 c = root.min + (glm::dvec2(x, y) + 0.5) * (root.max - root.min) / double(n);
                if (glm::length(c) < 0.3) {
                    ASSERT_EQ(r.cells[std::size_t(y) * n + x], 1);
                }
            }
    }
    // An annulus keeps its hole.
    std::vector<glm::dvec2> inner;
    for (auto p : circle) inner.push_back(p * 0.5);
    std::vector<glm::dvec2> outer;
    for (auto p : circle) outer.push_back(p * 2.0);
    const auto annulus = gp::rectilinear_region({outer, inner}, root, 0.05, 9);
    EXPECT_TRUE(annulus.topology_ok);
    const int n = 1 << annulus.depth;
    EXPECT_EQ(annulus.cells[std::size_t(n / 2) * n + n / 2], 0);  // the centre is in the hole
}

// Two bars crossing (the section of a surface through itself), each loop starting inside the other:
// by nesting each is the other's hole and no loop bounded a piece, and the region indexed an empty
// list (a crash on a part of the retrieval collection's figures). Now both are pieces, and the
// region, which no arrangement of loops that cross can match, reports its topology as wrong.
TEST(PolycubeQuadtree, LoopsThatCrossAreTwoPiecesNotTwoHoles) {
    const std::vector<glm::dvec2> across{{2.0, 1.0}, {4.0, 1.0}, {4.0, 2.0}, {0.0, 2.0}, {0.0, 1.0}};
    const std::vector<glm::dvec2> upright{{1.5, 1.5}, {1.5, -1.0}, {2.5, -1.0}, {2.5, 4.0}, {1.5, 4.0}};
    const auto r = gp::rectilinear_region({across, upright}, {{-1.0, -2.0}, {5.0, 5.0}}, 0.05, 7);
    EXPECT_DOUBLE_EQ(r.region_area, 4.0 + 5.0);
    ASSERT_EQ(r.component_of_loop.size(), 2u);
    EXPECT_NE(r.component_of_loop[0], r.component_of_loop[1]);
    EXPECT_FALSE(r.topology_ok);
}

// Two pairs of columns, the right one of the upper plane leaning left to within 0.03 of the lower
// plane's left column: each plane alone keeps its two regions apart, but the left region of the
// lower plane meets the right one of the upper (the polyhedron would join the columns there).
TEST(PolycubeQuadtree, NeighbouringLayersKeepUnjoinedPiecesApart) {
    const auto square = [](double x0, double x1) {
        return std::vector<glm::dvec2>{{x0, 0.0}, {x1, 0.0}, {x1, 1.0}, {x0, 1.0}};
    };
    std::vector<gp::polycube::Contour> contours(4);
    contours[0].plane = 0, contours[0].closed = square(0.0, 1.0);    // A0
    contours[1].plane = 0, contours[1].closed = square(1.3, 2.3);    // B0
    contours[2].plane = 1, contours[2].closed = square(0.0, 0.9);    // A1
    contours[3].plane = 1, contours[3].closed = square(1.03, 2.03);  // B1
    const std::vector<double> plane_z{0.0, 1.0};
    geo::Bounds box;
    box.min = {0.0, 0.0, -0.5}, box.max = {2.3, 1.0, 1.5};
    const gp::Rect root{{0.0, 0.0}, {2.3, 1.0}};
    const double da = 0.05;
    const std::uint32_t max_level = 8;

    // Per cell of the common grid, per layer: the component of A (0), of B (1) or none (-1).
    const auto touching_a0_b1 = [](const std::vector<std::int32_t>& lower, const std::vector<std::int32_t>& upper,
                                   std::int32_t a, std::int32_t b, int n) {
        std::size_t count = 0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                if (lower[std::size_t(y) * n + x] != a) continue;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int qx = x + dx, qy = y + dy;
                        if (qx >= 0 && qy >= 0 && qx < n && qy < n && upper[std::size_t(qy) * n + qx] == b) ++count;
                    }
            }
        return count;
    };
    const auto upsample = [](const gp::RectilinearRegion& r, std::uint32_t depth) {
        const int n = 1 << depth, shift = int(depth - r.depth), rn = 1 << r.depth;
        std::vector<std::int32_t> out(std::size_t(n) * n);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                out[std::size_t(y) * n + x] = r.owner[std::size_t(y >> shift) * rn + (x >> shift)];
        return out;
    };
    // Each plane alone: two regions apart, but across the layers A0 meets B1.
    const auto r0 = gp::rectilinear_region({contours[0].closed, contours[1].closed}, root, da, max_level);
    const auto r1 = gp::rectilinear_region({contours[2].closed, contours[3].closed}, root, da, max_level);
    ASSERT_TRUE(r0.topology_ok && r1.topology_ok);
    const std::uint32_t depth = std::max(r0.depth, r1.depth);
    ASSERT_GT(touching_a0_b1(upsample(r0, depth), upsample(r1, depth), r0.component_of_loop[0], r1.component_of_loop[1],
                             1 << depth),
              0u);

    // Stacked, with the mesh joining A0 to A1 and B0 to B1 only: nothing of A0 meets B1, nothing
    // was given up (refining was enough), and every cell centre inside a square is still in its region.
    gp::polycube::JoinedContours joined(3);
    joined[1] = {{0, 2}, {1, 3}};
    double excess = 0.0;
    std::size_t carved = 0;
    const auto layers = gp::polycube::stacked_regions(contours, plane_z, box, da, max_level, joined, excess, carved);
    const int n = 1 << layers.depth;
    EXPECT_EQ(carved, 0u);
    ASSERT_EQ(layers.joins[0].size(), 2u);
    const std::int32_t a0 = layers.owner[0][std::size_t(n / 2) * n + n / 5];
    const std::int32_t b1 = layers.owner[1][std::size_t(n / 2) * n + 3 * n / 4];
    ASSERT_GE(a0, 0);
    ASSERT_GE(b1, 0);
    EXPECT_FALSE(layers.joins[0].count({a0, b1}));
    EXPECT_EQ(touching_a0_b1(layers.owner[0], layers.owner[1], a0, b1, n), 0u);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const glm::dvec2 c = root.min + (glm::dvec2(x, y) + 0.5) * (root.max - root.min) / double(n);
            for (const auto& contour : contours)
                if (c.x > contour.closed[0].x && c.x < contour.closed[1].x) {
                    ASSERT_EQ(layers.cells[contour.plane][std::size_t(y) * n + x], 1) << x << " " << y;
                }
        }

    // Where the contours themselves overlap in projection, refining cannot help: the cells are given up.
    contours[3].closed = square(0.99, 1.99);
    const auto carved_layers =
        gp::polycube::stacked_regions(contours, plane_z, box, da, max_level, joined, excess, carved);
    EXPECT_GT(carved, 0u);
    const int m = 1 << carved_layers.depth;
    EXPECT_EQ(touching_a0_b1(carved_layers.owner[0], carved_layers.owner[1],
                             carved_layers.owner[0][std::size_t(m / 2) * m + m / 5],
                             carved_layers.owner[1][std::size_t(m / 2) * m + 3 * m / 4], m),
              0u);
}

// A hole narrower than the deepest cells meets no cell centre: the region would lose it (and a thin
// handle its tunnel), so the cell holding the point deepest inside the hole is left empty.
TEST(PolycubeQuadtree, AHoleNarrowerThanACellKeepsOneEmptyCell) {
    const std::vector<glm::dvec2> outer{{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}};
    const std::vector<glm::dvec2> hole{{0.30, 0.30}, {0.30, 0.36}, {0.36, 0.30}};  // inside cell (1, 1) of 4 x 4
    const gp::Rect root{{0.0, 0.0}, {1.0, 1.0}};
    const auto r = gp::rectilinear_region({outer, hole}, root, 0.05, 2);
    ASSERT_EQ(r.depth, 2u);
    EXPECT_TRUE(r.topology_ok);
    std::size_t empty = 0;
    for (std::size_t c = 0; c < r.cells.size(); ++c) empty += r.cells[c] == 0;
    EXPECT_EQ(empty, 1u);
    EXPECT_EQ(r.cells[1 * 4 + 1], 0);
}

// A pit that opens sideways between two planes: a hole on plane 0 whose contour the mesh joins to
// the outer contour of plane 1, over which layer 1 is solid. The hole's air gets a corridor in
// layer 1 out to the outside; without the join nothing is opened.
TEST(PolycubeLayers, EnclosedAirGetsAPassageWhereTheMeshJoinsIt) {
    const int n = 16;
    const gp::Rect root{{0.0, 0.0}, {1.0, 1.0}};
    const auto square = [](double a, double b) { return std::vector<glm::dvec2>{{a, a}, {b, a}, {b, b}, {a, b}}; };
    std::vector<gp::polycube::Contour> contours(3);
    contours[0].plane = 0, contours[0].closed = square(0.13, 0.87);  // outer, plane 0
    contours[1].plane = 0, contours[1].closed = square(0.38, 0.62);  // the hole, plane 0
    contours[2].plane = 1, contours[2].closed = square(0.13, 0.87);  // outer, plane 1
    const std::vector<std::int32_t> component{0, 0, 0};
    std::vector<std::vector<std::int32_t>> owner(2, std::vector<std::int32_t>(n * n, -1));
    for (int y = 2; y < 14; ++y)
        for (int x = 2; x < 14; ++x) {
            owner[1][y * n + x] = 0;
            if (x < 6 || x >= 10 || y < 6 || y >= 10) owner[0][y * n + x] = 0;
        }
    // Air cells of a layer reached from the grid's border through air.
    const auto open_air = [&](const std::vector<std::int32_t>& layer) {
        std::vector<std::uint8_t> seen(layer.size(), 0);
        std::vector<int> stack;
        for (int i = 0; i < n * n; ++i)
            if ((i % n == 0 || i / n == 0 || i % n == n - 1 || i / n == n - 1) && layer[i] < 0)
                seen[i] = 1, stack.push_back(i);
        while (!stack.empty()) {
            const int c = stack.back();
            stack.pop_back();
            for (const int d : {1, -1, n, -n}) {
                const int q = c + d;
                if (q < 0 || q >= n * n || (std::abs(d) == 1 && q / n != c / n) || seen[q] || layer[q] >= 0) continue;
                seen[q] = 1, stack.push_back(q);
            }
        }
        return seen;
    };
    const auto solid_pieces = [&](const std::vector<std::int32_t>& layer) {
        std::vector<std::uint8_t> seen(layer.size(), 0);
        std::size_t pieces = 0;
        for (int s = 0; s < n * n; ++s) {
            if (layer[s] < 0 || seen[s]) continue;
            ++pieces;
            std::vector<int> stack{s};
            seen[s] = 1;
            while (!stack.empty()) {
                const int c = stack.back();
                stack.pop_back();
                for (const int d : {1, -1, n, -n}) {
                    const int q = c + d;
                    if (q < 0 || q >= n * n || (std::abs(d) == 1 && q / n != c / n) || seen[q] || layer[q] < 0)
                        continue;
                    seen[q] = 1, stack.push_back(q);
                }
            }
        }
        return pieces;
    };

    gp::polycube::JoinedContours only_outer(3);
    only_outer[1] = {{0, 2}};
    auto unjoined = owner;
    EXPECT_EQ(gp::polycube::open_air_passages(unjoined, n, root, contours, component, only_outer), 0u);
    EXPECT_EQ(unjoined, owner);

    gp::polycube::JoinedContours joined(3);
    joined[1] = {{0, 2}, {1, 2}};
    auto opened = owner;
    EXPECT_GT(gp::polycube::open_air_passages(opened, n, root, contours, component, joined), 0u);
    EXPECT_EQ(opened[0], owner[0]);          // the hole's own layer keeps its hole
    EXPECT_EQ(solid_pieces(opened[1]), 1u);  // layer 1 stays one piece
    const auto reached = open_air(opened[1]);
    bool over_the_hole = false;
    for (int y = 6; y < 10; ++y)
        for (int x = 6; x < 10; ++x) over_the_hole = over_the_hole || reached[y * n + x];
    EXPECT_TRUE(over_the_hole);
}

// The loops of a section: a torus about y cut across its hole (two), past it (none); a sphere (one).
TEST(PolycubePlanes, SectionLoopsCountTheSection) {
    const geo::Mesh torus = geo::make_torus(1.0, 0.35, 48, 16);
    EXPECT_EQ(gp::polycube::section_loops(torus, 0.3), 2u);
    EXPECT_EQ(gp::polycube::section_loops(torus, 1.5), 0u);
    EXPECT_EQ(gp::polycube::section_loops(geo::make_icosphere(1.0, 3), 0.2), 1u);
}

// Cutting a smoothed copy carries the mesh's own positions through the cuts: with the true
// positions twice the copy's, every vertex's carried position is twice its sliced one.
TEST(PolycubePlanes, SlicingCarriesTheTruePositions) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 3);
    std::vector<glm::dvec3> carried;
    for (const auto& p : sphere.positions) carried.push_back(2.0 * p);
    const auto sliced = gp::polycube::slice_mesh(sphere, {-0.4, 0.1, 0.55}, &carried);
    ASSERT_EQ(carried.size(), sliced.mesh.vertex_count());
    ASSERT_GT(sliced.mesh.vertex_count(), sphere.vertex_count());
    for (std::size_t v = 0; v < carried.size(); ++v)
        ASSERT_NEAR(glm::length(carried[v] - 2.0 * sliced.mesh.positions[v]), 0.0, 1e-12) << v;
}

TEST(PolycubeBuild, AxisAlignedBoxGivesOneBox) {
    const geo::Mesh box = geo::make_box({2.0, 1.0, 1.0}, 4);
    const gp::Polycube p = gp::build_polycube(nullptr, box);
    expect_valid_polycube(p, 0);
    EXPECT_EQ(p.stats.polycube_faces, 6u);
    EXPECT_EQ(p.stats.polycube_corners, 8u);
    EXPECT_EQ(p.stats.quadtree_depth, 0u);
    const geo::Bounds b = p.surface.bounds();
    EXPECT_NEAR(glm::length(b.min - glm::dvec3(-1.0, -0.5, -0.5)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(b.max - glm::dvec3(1.0, 0.5, 0.5)), 0.0, 1e-12);
    // The map: one-to-one, every image on the box's surface.
    ASSERT_TRUE(p.stats.mapped) << p.stats.map_note;
    EXPECT_EQ(p.stats.flips, 0u);
    ASSERT_EQ(p.mapped.size(), box.vertex_count());
    for (const auto& q : p.mapped) {
        const double outside = std::max({std::abs(q.x) - 1.0, std::abs(q.y) - 0.5, std::abs(q.z) - 0.5});
        ASSERT_NEAR(outside, 0.0, 1e-9);
    }
    EXPECT_GE(p.stats.area_distortion, 1.0);
}

TEST(PolycubeBuild, TorusIsAValidGenusOnePolycubeWithAFlipFreeMap) {
    const geo::Mesh torus = geo::make_torus(1.0, 0.35, 48, 16);
    const gp::Polycube p = gp::build_polycube(nullptr, torus);
    expect_valid_polycube(p, 1);
    EXPECT_EQ(p.stats.genus, 1u);
    EXPECT_EQ(p.stats.saddles, 2u);
    ASSERT_TRUE(p.stats.mapped) << p.stats.map_note;
    EXPECT_EQ(p.stats.flips, 0u);
    // A vertex exactly on a plane maps onto that plane's loop, at the plane's height.
    EXPECT_LT(p.stats.boundary_snap, 0.05);
    EXPECT_GE(p.stats.area_distortion, 1.0);
    EXPECT_GE(p.stats.angle_distortion, 1.0);
    // The chart smoothing never turns a triangle that was not turned, and keeps every image on the
    // polycube (its faces' planes, within the polycube's bounds).
    EXPECT_GT(p.stats.smoothing_moves, 0u);
    EXPECT_LE(p.stats.turned_chords, p.stats.turned_chords_unsmoothed);
    const geo::Bounds b = p.surface.bounds();
    for (const auto& q : p.mapped) {
        for (int k = 0; k < 3; ++k) ASSERT_TRUE(q[k] >= b.min[k] - 1e-12 && q[k] <= b.max[k] + 1e-12);
    }
    gp::PolycubeOptions raw;
    raw.smoothing = 0;
    const gp::Polycube unsmoothed = gp::build_polycube(nullptr, torus, raw);
    EXPECT_EQ(unsmoothed.stats.smoothing_moves, 0u);
    EXPECT_EQ(unsmoothed.stats.turned_chords, p.stats.turned_chords_unsmoothed);
    EXPECT_DOUBLE_EQ(unsmoothed.stats.area_distortion, p.stats.area_distortion_unsmoothed);
}

TEST(PolycubeBuild, OpenUprightCylinderKeepsItsEndsAsHoles) {
    const geo::Mesh tube = open_cylinder(32, 16, false);
    gp::PolycubeOptions o;
    o.da = 10.0;  // coarse enough for one cell per plane: a box
    const gp::Polycube p = gp::build_polycube(nullptr, tube, o);
    expect_valid_polycube(p, 0);
    EXPECT_EQ(p.stats.holes, 2u);
    EXPECT_EQ(p.stats.holes_marked, 2u);
    EXPECT_EQ(p.stats.polycube_faces, 6u);
    EXPECT_EQ(p.stats.chains, 0u);  // no plane crosses an end
    ASSERT_TRUE(p.stats.mapped) << p.stats.map_note;
    EXPECT_EQ(p.stats.flips, 0u);
    // The ends map onto the box's top and bottom faces, spilling onto the walls only beyond the
    // first and last planes (the caps' slab pieces).
    ASSERT_GT(p.stats.hole_triangles, 0u);
    const double first = p.planes.front().z, last = p.planes.back().z;
    bool top = false, bottom = false;
    for (std::size_t f = 0; f < p.surface.face_count(); ++f) {
        if (!p.hole[f]) continue;
        top = top || p.face_axis[f] == 4;
        bottom = bottom || p.face_axis[f] == 5;
        const auto& t = p.surface.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const double z = p.surface.positions[t[k]].z;
            EXPECT_TRUE(z <= first + 1e-12 || z >= last - 1e-12) << "hole at z = " << z;
        }
    }
    EXPECT_TRUE(top && bottom);
}

TEST(PolycubeBuild, SideHoleIsClosedInItsPlanesAndMarkedOnTheWall) {
    const geo::Mesh tube = open_cylinder(32, 32, true);
    const gp::Polycube p = gp::build_polycube(nullptr, tube);
    expect_valid_polycube(p, 0);
    EXPECT_EQ(p.stats.holes, 3u);
    EXPECT_GT(p.stats.chains, 0u);
    EXPECT_EQ(p.stats.holes_marked, 3u);
    EXPECT_EQ(p.stats.chains,
              p.stats.closed_by_bezier + p.stats.closed_by_fallback + p.stats.closed_by_chord + p.stats.closing_failed);
    EXPECT_EQ(p.stats.closing_failed, 0u);
    // The closed sections stay within a few percent of the circle.
    for (const auto& plane : p.closed_contours)
        for (const auto& loop : plane)
            for (const auto& q : loop) EXPECT_NEAR(glm::length(q), 1.0, 0.06);
    ASSERT_TRUE(p.stats.mapped) << p.stats.map_note;
    EXPECT_EQ(p.stats.flips, 0u);
    bool on_wall = false;
    for (std::size_t f = 0; f < p.surface.face_count(); ++f)
        if (p.hole[f] && p.face_axis[f] < 4) {
            on_wall = true;
            EXPECT_GT(p.surface.positions[p.surface.triangles[f][0]].x, 0.0);  // the hole is on the +x side
        }
    EXPECT_TRUE(on_wall);
}

TEST_F(PolycubeGpu, BuildOnTheGpuMatchesTheCpuTwin) {
    const geo::Mesh torus = geo::make_torus(1.0, 0.35, 48, 16);
    const gp::Polycube gpu = gp::build_polycube(&ctx(), torus);
    const gp::Polycube cpu = gp::build_polycube(nullptr, torus);
    EXPECT_EQ(gpu.stats.planes, cpu.stats.planes);
    EXPECT_EQ(gpu.stats.polycube_triangles, cpu.stats.polycube_triangles);
    ASSERT_TRUE(gpu.stats.mapped);
    ASSERT_EQ(gpu.mapped.size(), cpu.mapped.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < gpu.mapped.size(); ++i)
        worst = std::max(worst, glm::length(gpu.mapped[i] - cpu.mapped[i]));
    EXPECT_LT(worst, 1e-4);
    EXPECT_EQ(gpu.stats.flips, 0u);
}

TEST(PolycubeBuild, AutoAxisTakesZFirst) {
    const gp::Polycube p = gp::build_polycube(nullptr, geo::make_torus(1.0, 0.35, 48, 16));
    EXPECT_EQ(p.stats.axis, 2);
    EXPECT_EQ(p.stats.axes_tried, 1u);
}

TEST(PolycubeBuild, SlicingAxisIsAPermutation) {
    geo::Mesh box = geo::make_box({1.0, 2.0, 3.0}, 2);
    gp::PolycubeOptions o;
    o.axis = 0;
    const gp::Polycube p = gp::build_polycube(nullptr, box, o);
    expect_valid_polycube(p, 0);
    const geo::Bounds b = p.surface.bounds();
    EXPECT_NEAR(b.max.x, 0.5, 1e-12);
    EXPECT_NEAR(b.max.y, 1.0, 1e-12);
    EXPECT_NEAR(b.max.z, 1.5, 1e-12);
}

TEST(PolycubeBuild, RefusesWhatItCannotTake) {
    geo::Mesh two = geo::make_icosphere(1.0, 1);
    const geo::Mesh other = geo::make_icosphere(1.0, 1, {5.0, 0.0, 0.0});
    const std::uint32_t base = std::uint32_t(two.positions.size());
    two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
    for (auto t : other.triangles) two.triangles.push_back(t + glm::uvec3(base));
    EXPECT_THROW(gp::build_polycube(nullptr, two), geo::InputError);
    // Flat, in z or standing in the xz-plane and tilted (whose slices normal to z were segments, and
    // failed with "internal: a contour parameter was not found"): closed off, no volume.
    geo::Mesh standing = geo::make_grid(4, 4), tilted = geo::make_grid(4, 4);
    for (auto& p : standing.positions) p = {p.x, 0.5, p.y};
    for (auto& p : tilted.positions) p = {p.x, 0.3 * p.y, p.y};
    for (const geo::Mesh& flat : {geo::make_grid(4, 4), standing, tilted}) try {
            gp::build_polycube(nullptr, flat);
            ADD_FAILURE() << "a flat grid made a polycube";
        } catch (const geo::InputError& e) {
            EXPECT_NE(std::string(e.what()).find("the mesh is flat"), std::string::npos) << e.what();
        }
    gp::PolycubeOptions bad;
    bad.da = 0.0;
    EXPECT_THROW(gp::build_polycube(nullptr, geo::make_icosphere(1.0, 1), bad), geo::InputError);
    bad = {};
    bad.axis = 4;
    EXPECT_THROW(gp::build_polycube(nullptr, geo::make_icosphere(1.0, 1), bad), geo::InputError);
    bad = {};
    bad.retry_seconds = -1.0;
    EXPECT_THROW(gp::build_polycube(nullptr, geo::make_icosphere(1.0, 1), bad), geo::InputError);
}

// The cow's legs and horns stand closer than the coarse cells: the layers must keep them apart.
TEST(PolycubeSharedMeshes, CowHasAValidPolycubeAndAFlipFreeMap) {
    GIMG_REQUIRE_SHARED_MESH(cow, "cow.off");
    const gp::Polycube p = gp::build_polycube(nullptr, geo::load_mesh(cow));
    expect_valid_polycube(p, 0);
    EXPECT_EQ(p.stats.axis, 2);  // along z, the first tried
    ASSERT_TRUE(p.stats.mapped) << p.stats.map_note;
    EXPECT_EQ(p.stats.flips, 0u);
}

// The femur's head is pitted and its two handles are tunnels about 0.001 of its length: the
// first construction fails, the retry on a smoothed copy succeeds with both handles kept.
TEST(PolycubeSharedMeshes, PittedFemurIsBuiltOnARetry) {
    GIMG_REQUIRE_SHARED_MESH(femur, "femur.off");
    gp::PolycubeOptions o;
    o.axis = 2;
    std::vector<gp::PolycubeStatistics> failed;
    const gp::Polycube p = gp::build_polycube(nullptr, geo::load_mesh(femur), o,
                                              [&](const gp::PolycubeStatistics& s) { failed.push_back(s); });
    expect_valid_polycube(p, 2);
    EXPECT_GT(p.stats.attempts, 1u);
    ASSERT_EQ(failed.size(), p.stats.attempts - 1);  // told of every failed attempt before the last
    EXPECT_EQ(failed.front().attempts, 1u);
    EXPECT_EQ(failed.front().slice_smoothing, 0u);
    EXPECT_FALSE(gp::failure_of(failed.front(), true).empty());
    EXPECT_GE(p.stats.slice_smoothing, 3u);
    EXPECT_GT(p.stats.cells_opened, 0u);  // pits that open between planes got their passages
    ASSERT_TRUE(p.stats.mapped) << p.stats.map_note;
    EXPECT_EQ(p.stats.flips, 0u);
    EXPECT_EQ(p.mapped.size(), 3897u);
}

// The turbine's polycube side of a slab piece is coarse enough that shortest cuts between its loops
// wall each other off; split finer, it maps on the first attempt along z.
TEST(PolycubeSharedMeshes, TurbineMapsOnItsFirstAttempt) {
    GIMG_REQUIRE_SHARED_MESH(turbine, "turbine.off");
    gp::PolycubeOptions o;
    o.axis = 2;
    o.retry = false;
    const gp::Polycube p = gp::build_polycube(nullptr, geo::load_mesh(turbine), o);
    expect_valid_polycube(p, 11);
    ASSERT_TRUE(p.stats.mapped) << p.stats.map_note;
    EXPECT_EQ(p.stats.cut_mismatch, 0u);
    EXPECT_EQ(p.stats.flips, 0u);
}

TEST(PolycubeSharedMeshes, DoubleTorusAndAnOpenScan) {
    GIMG_REQUIRE_SHARED_MESH(eight, "eight.off");
    const gp::Polycube p = gp::build_polycube(nullptr, geo::load_mesh(eight));
    expect_valid_polycube(p, 2);
    ASSERT_TRUE(p.stats.mapped) << p.stats.map_note;
    EXPECT_EQ(p.stats.flips, 0u);
    GIMG_REQUIRE_SHARED_MESH(holes, "holes.off");
    const gp::Polycube h = gp::build_polycube(nullptr, geo::load_mesh(holes));
    expect_valid_polycube(h, 0);
    EXPECT_EQ(h.stats.holes, 7u);
    EXPECT_GT(h.stats.closed_by_bezier, 0u);
    EXPECT_GT(h.stats.closed_by_fallback, 0u);
    ASSERT_TRUE(h.stats.mapped) << h.stats.map_note;
    EXPECT_EQ(h.stats.flips, 0u);
    EXPECT_GT(h.stats.hole_triangles, 0u);
    EXPECT_EQ(h.stats.holes_marked, 7u);
}

// The paper's cylindrical Z-buffer on the CPU (passes/cylinder/scanline.cpp): pixel-for-pixel
// agreement with a brute-force evaluation of the exact definition (a ray per pixel against every
// triangle) where the answer has no closed form, watertightness, threads, bad input. The analytic
// cases every method passes are in test_cylinder_analytic.cpp.
#include "cylinder_analytic_cases.h"
#include "cylinder_exact.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"
#include "gimg/passes/cylinder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

using namespace gimg;
using gimg::test::Agreement;
using gimg::test::brute_force;
using gimg::test::compare;
using gimg::test::soup;
using gimg::test::theta_of;
using gimg::test::y_of;

TEST(CylinderScanline, TriangleFarFromTheAxisHasCurvedEdges) {
    // Spanning 100 degrees at radius ~0.8 and most of the height: its edges bow visibly in
    // (theta, y), so a rasterizer joining the projected corners by straight lines would be wrong.
    // Facing outwards it is seen directly; wound the other way round it faces the axis and is
    // seen through it, half a turn away, with d < 0.
    auto at = [](double r, double degrees, double y) {
        const double a = degrees * std::numbers::pi / 180.0;
        return glm::dvec3(r * std::cos(a), y, r * std::sin(a));
    };
    const glm::dvec3 p0 = at(0.85, -40.0, 0.1), p1 = at(0.9, 10.0, 0.95), p2 = at(0.8, 60.0, 0.3);
    for (const bool through_the_axis : {false, true}) {
        const std::vector<glm::dvec3> corners = through_the_axis ? std::vector{p0, p2, p1} : std::vector{p0, p1, p2};
        const passes::CylinderMesh mesh = soup(corners);
        const std::uint32_t W = 720, H = 360;
        const auto img = passes::cylinder_scanline(mesh, W, H);
        const auto exact = brute_force(mesh, W, H);
        const Agreement a = compare(img, exact);
        EXPECT_GT(a.covered, 10000u);
        EXPECT_EQ(a.coverage_differs, 0u);
        EXPECT_EQ(a.depth_differs, 0u) << "max |delta d| " << a.max_depth_error;

        // How many pixels the straight-edged triangle between the projected corners gets wrong.
        const double turn = through_the_axis ? std::numbers::pi : 0.0, centre = 10.0 * std::numbers::pi / 180.0 + turn;
        glm::dvec2 q[3];
        for (int k = 0; k < 3; ++k) q[k] = {std::atan2(corners[k].z, corners[k].x) + turn, corners[k].y};
        auto side = [](glm::dvec2 s0, glm::dvec2 s1, glm::dvec2 p) {
            return (s1.x - s0.x) * (p.y - s0.y) - (s1.y - s0.y) * (p.x - s0.x);
        };
        std::size_t straight_edges_wrong = 0, back = 0;
        for (std::uint32_t v = 0; v < H; ++v)
            for (std::uint32_t u = 0; u < W; ++u) {
                const double th = centre + std::remainder(theta_of(u, W) - centre, 2.0 * std::numbers::pi);
                const glm::dvec2 p{th, y_of(v, H)};
                const double s0 = side(q[0], q[1], p), s1 = side(q[1], q[2], p), s2 = side(q[2], q[0], p);
                const bool inside = (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
                const std::size_t i = img.index(u, v);
                straight_edges_wrong += inside != bool(img.covered[i]);
                back += img.covered[i] && img.distance[i] < 0.0f;
            }
        std::printf("curved triangle%s: %zu pixels covered, straight edges would get %zu wrong\n",
                    through_the_axis ? " (through the axis)" : "", a.covered, straight_edges_wrong);
        EXPECT_GT(straight_edges_wrong, 200u);
        EXPECT_EQ(back, through_the_axis ? a.covered : 0u);
    }
}

TEST(CylinderScanline, RandomTriangleSoupMatchesTheDefinition) {
    // Triangles of all sizes anywhere in the cylinder, many across the axis (exception
    // triangles), across the seam, seen through the axis, poking out of the wall; through a
    // transform, so that path is checked too.
    std::mt19937 rng(2006);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<glm::dvec3> corners;
    std::size_t exceptions = 0;
    const int count = 300;
    for (int k = 0; k < count; ++k) {
        const double r = 0.95 * unit(rng), a = 2.0 * std::numbers::pi * unit(rng);  // denser near the axis
        const glm::dvec3 centre{r * std::cos(a), unit(rng), r * std::sin(a)};
        const double size = k % 10 == 0 ? 0.8 : 0.05 + 0.35 * unit(rng);
        glm::dvec3 tri[3];
        for (glm::dvec3& p : tri) p = centre + size * glm::dvec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
        const glm::dvec3 n = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
        double s[3];
        for (int i = 0; i < 3; ++i) s[i] = tri[i].x * n.x + tri[i].z * n.z;
        exceptions += std::min({s[0], s[1], s[2]}) < 0.0 && std::max({s[0], s[1], s[2]}) > 0.0;
        corners.insert(corners.end(), tri, tri + 3);
    }
    // A quarter turn about y, scaled by 0.9 and raised by 0.05: still inside the cylinder.
    const passes::CylinderTransform m{0, 0, -0.9f, 0, 0, 0.9f, 0, 0.05f, 0.9f, 0, 0, 0};
    const passes::CylinderMesh mesh = soup(corners);
    const std::uint32_t W = 360, H = 180;
    const auto img = passes::cylinder_scanline(mesh, W, H, m);
    const Agreement a = compare(img, brute_force(mesh, W, H, m));
    std::printf(
        "soup: %zu exception triangles, %zu covered pixels, coverage differs at %zu, depth at %zu "
        "(max |delta d| %.3g)\n",
        exceptions, a.covered, a.coverage_differs, a.depth_differs, a.max_depth_error);
    EXPECT_GT(exceptions, 20u);
    EXPECT_GT(a.covered, W * H / 2);
    EXPECT_LE(a.coverage_differs, W * H / 2000) << "more than 0.05 % of the pixels";
    EXPECT_LE(a.depth_differs, W * H / 2000) << "more than 0.05 % of the pixels";
}

TEST(CylinderScanline, WatertightWhereEdgesPassThroughPixelCentres) {
    // A closed barrel whose corners sit on the rays of every third column and whose rings lie at
    // the heights of every eighth row (exact in float for H = 64): many pixel lines run along an
    // edge, shared by two triangles; none may fall through between them. Facets cross the seam.
    const std::uint32_t W = 96, H = 64, step = 3;
    const auto dirs = passes::cylinder_directions(W);
    geo::Mesh barrel;
    const std::uint32_t rings = 5, n = W / step;
    for (std::uint32_t i = 0; i < rings; ++i) {
        const double y = y_of(8 + 8 * i, H), r = 0.5 + 0.08 * i;  // widening downwards: slanted facets
        for (std::uint32_t k = 0; k < n; ++k)
            barrel.positions.push_back({r * dirs[k * step][0], y, r * dirs[k * step][1]});
    }
    for (std::uint32_t i = 0; i + 1 < rings; ++i)
        for (std::uint32_t k = 0; k < n; ++k) {
            const std::uint32_t a = i * n + k, b = i * n + (k + 1) % n, c = a + n, d = b + n;
            barrel.triangles.push_back({a, b, d});  // outward: counter-clockwise seen from outside
            barrel.triangles.push_back({a, d, c});
        }
    const passes::CylinderMesh mesh = test::to_cylinder_mesh(barrel);
    const auto img = passes::cylinder_scanline(mesh, W, H);
    for (std::uint32_t v = 0; v < H; ++v)
        for (std::uint32_t u = 0; u < W; ++u) {
            const bool inside = v >= 8 && v <= 8 + 8 * (rings - 1);
            ASSERT_EQ(bool(img.covered[img.index(u, v)]), inside) << u << "," << v;
        }
    // Where a ring's edges lie exactly in a pixel row, Moller-Trumbore's own rounding lets some
    // of those lines slip between its triangles; the scanline must cover everything it covers.
    const auto exact = brute_force(mesh, W, H);
    std::size_t only_exact = 0, only_scanline = 0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
        only_exact += !img.covered[i] && !std::isnan(exact[i]);
        only_scanline += img.covered[i] && std::isnan(exact[i]);
    }
    std::printf("barrel: ray casting lets %zu pixel lines through between triangles, the scanline none\n",
                only_scanline);
    EXPECT_EQ(only_exact, 0u);
    EXPECT_EQ(compare(img, exact).depth_differs, 0u);
}

TEST(CylinderScanline, ThreadCountDoesNotChangeTheImage) {
    const geo::Mesh sphere = geo::make_icosphere(0.3, 5, {0.35, 0.5, -0.2});
    const passes::CylinderMesh mesh = test::to_cylinder_mesh(sphere);
    const auto one = passes::cylinder_scanline(mesh, 300, 150, passes::kIdentityTransform, 1);
    const auto three = passes::cylinder_scanline(mesh, 300, 150, passes::kIdentityTransform, 3);
    EXPECT_EQ(one.covered, three.covered);
    EXPECT_EQ(one.distance, three.distance);
}

TEST(CylinderScanline, BadInputIsRejectedOrSkipped) {
    passes::CylinderMesh mesh = soup({{0.5, 0.2, 0.0}, {0.5, 0.8, 0.2}, {0.5, 0.2, 0.4}});
    EXPECT_THROW(passes::cylinder_scanline(mesh, 0, 10), geo::InputError);
    passes::CylinderMesh missing = mesh;
    missing.triangles[1] = 7;
    EXPECT_THROW(passes::cylinder_scanline(missing, 10, 10), geo::InputError);
    // A triangle with a non-finite corner is skipped, on one thread or several; the others are drawn.
    passes::CylinderMesh with_nan = soup({{0.5, 0.2, 0.0},
                                          {0.5, 0.8, 0.2},
                                          {0.5, 0.2, 0.4},
                                          {0.1, 0.1, 0.1},
                                          {std::nan(""), 0.5, 0.1},
                                          {0.2, 0.9, 0.1}});
    const auto clean = passes::cylinder_scanline(mesh, 64, 32);
    for (unsigned threads : {1u, 2u}) {
        const auto img = passes::cylinder_scanline(with_nan, 64, 32, passes::kIdentityTransform, threads);
        EXPECT_EQ(img.covered, clean.covered);
        EXPECT_EQ(img.distance, clean.distance);
    }
    const auto empty = passes::cylinder_scanline(passes::CylinderMesh{}, 8, 4);
    EXPECT_EQ(std::count(empty.covered.begin(), empty.covered.end(), 1), 0);
}

// `gimg quadmap --corners auto` (flattest_square_corners): a square around the flattest vertex,
// taken the other way round where it would wrap a part of the mesh, halved until its sides cut a
// disk, on the centre's own piece of the mesh, and refused with its reason where nothing cuts.
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/normals.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/quad_region.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>

using namespace gimg;
namespace gp = gimg::passes;

TEST(QuadRegionCut, AutomaticCornersGatherTheSquareNotTheRestOfTheMesh) {
    // On camel at 0.25 diagonals the square around the flattest vertex is wider than the head, its
    // sides run round it, and corners counter-clockwise about the normal put the body on their left.
    GIMG_REQUIRE_SHARED_MESH(path, "camel.off");
    const geo::Mesh camel = geo::load_mesh(path);
    const auto area = [](const geo::Mesh& m) {
        const std::vector<double> a = geo::face_areas(m);
        return std::accumulate(a.begin(), a.end(), 0.0);
    };
    const gp::QuadRegionCutter cutter(camel);
    std::array<std::uint32_t, 4> corners = gp::flattest_square_corners(cutter, 0.25);
    const gp::QuadRegion square = cutter.cut(corners, false);
    EXPECT_LT(area(square.mesh), 0.25 * area(camel));
    std::swap(corners[1], corners[3]);  // the other way round: the rest of the camel
    EXPECT_GT(area(cutter.cut(corners, false).mesh), 0.75 * area(camel));
    // Its map spreads over the square: no tenth of the square's width holds half the vertices.
    const gp::QuadMap m = gp::map_quad_region(nullptr, square, {.solver = gp::QuadSolver::Direct});
    EXPECT_EQ(m.flipped, 0u);
    std::array<std::size_t, 10> columns{};
    for (const auto& p : m.uv) ++columns[std::min<std::size_t>(9, std::size_t(p.x * 10.0))];
    EXPECT_LT(*std::max_element(columns.begin(), columns.end()), m.uv.size() / 2);
}

// A 20 x 20 grid lifted by r^4 / 10^4 about its centre, flattest there, with a hole 3 to 4 from it
// when `hole`: the square of 0.3 diagonals (half side 4.3) would enclose the hole, so the automatic
// corners take the square of half that side, which stays clear of it.
TEST(QuadRegionCut, AutomaticCornersHalveTheSquareUntilItCutsADisk) {
    auto sheet = [](bool hole) {
        geo::Mesh m;
        for (int j = 0; j <= 20; ++j)
            for (int i = 0; i <= 20; ++i) {
                const double r2 = (i - 10.0) * (i - 10.0) + (j - 10.0) * (j - 10.0);
                m.positions.push_back({double(i), double(j), 1e-4 * r2 * r2});
            }
        for (std::uint32_t j = 0; j < 20; ++j)
            for (std::uint32_t i = 0; i < 20; ++i) {
                if (hole && i == 13 && (j == 9 || j == 10)) continue;
                const std::uint32_t v = j * 21 + i;
                m.triangles.push_back({v, v + 1, v + 22});
                m.triangles.push_back({v, v + 22, v + 21});
            }
        return m;
    };
    const auto area = [](const geo::Mesh& m) {
        const std::vector<double> a = geo::face_areas(m);
        return std::accumulate(a.begin(), a.end(), 0.0);
    };
    const geo::Mesh whole = sheet(false), holed = sheet(true);
    const gp::QuadRegionCutter whole_cutter(whole), holed_cutter(holed);
    const gp::QuadRegion big = whole_cutter.cut(gp::flattest_square_corners(whole_cutter, 0.3), false);
    EXPECT_GT(area(big.mesh), 50.0);  // about 8.6 x 8.6
    const gp::QuadRegion small = holed_cutter.cut(gp::flattest_square_corners(holed_cutter, 0.3), false);
    EXPECT_LT(area(small.mesh), 30.0);  // about 4.3 x 4.3
    EXPECT_GT(area(small.mesh), 9.0);
    for (const glm::dvec3& p : small.mesh.positions) {
        EXPECT_LT(std::abs(p.x - 10.0), 3.0);
        EXPECT_LT(std::abs(p.y - 10.0), 3.0);
    }
    // An icosahedron's vertices are too far apart for any square about one to have four distinct
    // corners: refused, saying so.
    try {
        (void)gp::flattest_square_corners(gp::QuadRegionCutter(geo::make_icosphere(1.0, 0)), 0.3);
        ADD_FAILURE() << "no square about an icosahedron's vertex cuts a region";
    } catch (const geo::InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("automatic corners: no square of side 0.3 to 0.01875"), std::string::npos) << message;
        EXPECT_NE(message.find("(at 0.3: the corners must be distinct vertices)"), std::string::npos) << message;
    }
}

// teapot's 32 pieces: the square's corners stay on the flattest vertex's piece, so they cut.
TEST(QuadRegionCut, AutomaticCornersStayOnTheCentresPiece) {
    GIMG_REQUIRE_SHARED_MESH(path, "teapot.obj");
    const geo::Mesh teapot = geo::load_mesh(path);
    const gp::QuadRegionCutter cutter(teapot);
    const std::array<std::uint32_t, 4> corners = gp::flattest_square_corners(cutter);
    EXPECT_NO_THROW((void)cutter.cut(corners, false));
}

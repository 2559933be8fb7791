// The procedural shapes are what their documentation says: counts, closure (every edge in two
// faces), outward orientation (positive signed volume) and the analytic volume or area.
#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

using namespace gimg::geo;

namespace {
double signed_volume(const Mesh& m) {
    double v = 0.0;
    for (const auto& t : m.triangles)
        v += glm::dot(m.positions[t.x], glm::cross(m.positions[t.y], m.positions[t.z])) / 6.0;
    return v;
}
// Each directed edge appears once and its reverse once: closed and consistently oriented.
bool closed_and_oriented(const Mesh& m) {
    std::map<std::pair<unsigned, unsigned>, int> directed;
    for (const auto& t : m.triangles) {
        const unsigned c[3] = {t.x, t.y, t.z};
        for (int k = 0; k < 3; ++k) ++directed[{c[k], c[(k + 1) % 3]}];
    }
    for (const auto& [e, n] : directed)
        if (n != 1 || directed.count({e.second, e.first}) != 1) return false;
    return true;
}
}  // namespace

TEST(Shapes, IcosphereCountsClosureAndVolume) {
    Mesh s = make_icosphere(2.0, 4);
    EXPECT_EQ(s.vertex_count(), 10u * 256u + 2u);
    EXPECT_EQ(s.face_count(), 20u * 256u);
    EXPECT_TRUE(closed_and_oriented(s));
    for (const auto& p : s.positions) ASSERT_NEAR(glm::length(p), 2.0, 1e-12);
    const double sphere = 4.0 / 3.0 * std::numbers::pi * 8.0;
    EXPECT_LT(signed_volume(s), sphere);  // inscribed polyhedron
    EXPECT_GT(signed_volume(s), 0.99 * sphere);
}

TEST(Shapes, BoxIsClosedOutwardWithTheRightVolume) {
    Mesh b = make_box({1.0, 2.0, 3.0}, 3);
    EXPECT_TRUE(closed_and_oriented(b));
    EXPECT_NEAR(signed_volume(b), 6.0, 1e-12);
    EXPECT_EQ(b.vertex_count(), 4u * 4u * 4u - 2u * 2u * 2u);  // the lattice's surface points
}

TEST(Shapes, TorusIsClosedWithTheRightVolume) {
    Mesh t = make_torus(2.0, 0.5, 64, 32);
    EXPECT_TRUE(closed_and_oriented(t));
    const double exact = 2.0 * std::numbers::pi * std::numbers::pi * 2.0 * 0.25;
    EXPECT_NEAR(signed_volume(t), exact, 0.01 * exact);
}

TEST(Shapes, GridHasTexcoordsMatchingPositions) {
    Mesh g = make_grid(4, 3, 2.0, 3.0);
    ASSERT_TRUE(g.has_texcoords());
    EXPECT_EQ(g.face_count(), 24u);
    for (std::size_t i = 0; i < g.vertex_count(); ++i) {
        EXPECT_DOUBLE_EQ(g.texcoords[i].x * 2.0, g.positions[i].x);
        EXPECT_DOUBLE_EQ(g.texcoords[i].y * 3.0, g.positions[i].y);
    }
}

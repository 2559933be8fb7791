// The polycube map's piece bookkeeping: boundary loops (each from its smallest vertex, a repeated
// corner no boundary of its own) and vertex_at, which keeps a loop as boundary_loops would give it
// while it splits the loop's edges.
#include "gimg/geometry/error.h"
#include "polycube/piece_disks.h"
#include "polycube/polycube_parts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

using namespace gimg;
namespace gp = gimg::passes;

// Boundary loops: each from its smallest vertex, in the order of those; a triangle's repeated corner
// makes no boundary of its own (the degenerate (0, 1, 1) closes the edge 0 1 and leaves the chain
// 1 -> 2 -> 0 open); a vertex with two outgoing boundary edges is refused.
TEST(PolycubePieceDisks, BoundaryLoopsStartAtTheirSmallestVertex) {
    using Loops = std::vector<std::vector<std::uint32_t>>;
    EXPECT_EQ(gp::polycube::boundary_loops({{4, 5, 3}, {2, 0, 1}}), (Loops{{0, 1, 2}, {3, 4, 5}}));
    try {
        (void)gp::polycube::boundary_loops({{0, 1, 2}, {0, 1, 1}});
        ADD_FAILURE() << "an open chain makes no loop";
    } catch (const geo::InputError& e) {
        EXPECT_STREQ(e.what(), "a boundary chain ends at vertex 0");
    }
    EXPECT_THROW((void)gp::polycube::boundary_loops({{0, 1, 2}, {0, 3, 4}}), geo::InputError);
}

// A hexagon fanned from its centre: its one loop runs 1..6 from the smallest vertex. Splitting its
// edges at contour parameters adds vertices that vertex_at puts into the loop as boundary_loops
// would (the map's cuts read the loop from there instead of from the triangles): between 2 and 3,
// and on the closing edge 6 -> 1, where the parameter wraps.
TEST(PolycubePieceDisks, VertexAtKeepsTheLoopBoundaryLoopsGives) {
    gp::polycube::Local m;
    std::vector<glm::dvec3> ring;
    std::vector<double> ring_u;
    m.pos.push_back(glm::dvec3(0.0));
    m.contour.push_back(-1);
    m.u.push_back(0.0);
    for (int k = 0; k < 6; ++k) {
        const double a = std::numbers::pi * k / 3.0;
        ring.push_back({std::cos(a), std::sin(a), 0.0});
        ring_u.push_back(k / 6.0);
        m.pos.push_back(ring.back());
        m.contour.push_back(0);
        m.u.push_back(ring_u.back());
    }
    for (std::uint32_t k = 1; k <= 6; ++k) {
        m.tri.push_back({0u, k, k % 6 + 1});
        m.tri_source.push_back(k - 1);
    }
    m.global.assign(m.pos.size(), gp::polycube::kNone);
    for (std::uint32_t v = 0; v < m.pos.size(); ++v) m.origin.push_back(v);
    auto loops = gp::polycube::boundary_loops(m.tri);
    ASSERT_EQ(loops, (std::vector<std::vector<std::uint32_t>>{{1, 2, 3, 4, 5, 6}}));

    EXPECT_EQ(gp::polycube::vertex_at(m, loops[0], 2.0 / 6.0, ring, ring_u), 3u);  // already there
    EXPECT_EQ(m.pos.size(), 7u);
    EXPECT_EQ(gp::polycube::vertex_at(m, loops[0], 0.25, ring, ring_u), 7u);
    EXPECT_EQ(loops, (std::vector<std::vector<std::uint32_t>>{{1, 2, 7, 3, 4, 5, 6}}));
    EXPECT_NEAR(glm::length(m.pos[7] - 0.5 * (ring[1] + ring[2])), 0.0, 1e-12);
    EXPECT_EQ(gp::polycube::vertex_at(m, loops[0], 0.95, ring, ring_u), 8u);
    EXPECT_EQ(loops, (std::vector<std::vector<std::uint32_t>>{{1, 2, 7, 3, 4, 5, 6, 8}}));
    EXPECT_EQ(loops, gp::polycube::boundary_loops(m.tri));
    EXPECT_EQ(m.tri.size(), 8u);
}

// Splitting every triangle in four: a loop edge's midpoint joins its loop halfway in parameter (on
// the closing edge, where the parameter wraps, past the last vertex), a spoke's or a chord's stays
// inside; the split triangles keep their source and the surface is the same.
TEST(PolycubePieceDisks, SubdivideKeepsTheLoopsAndTheSurface) {
    gp::polycube::Local m;
    m.pos.push_back(glm::dvec3(0.0));
    m.contour.push_back(-1);
    m.u.push_back(0.0);
    for (int k = 0; k < 6; ++k) {
        const double a = std::numbers::pi * k / 3.0;
        m.pos.push_back({std::cos(a), std::sin(a), 0.0});
        m.contour.push_back(0);
        m.u.push_back(k / 6.0);
    }
    for (std::uint32_t k = 1; k <= 6; ++k) {
        m.tri.push_back({0u, k, k % 6 + 1});
        m.tri_source.push_back(10 + k);
    }
    m.global.assign(m.pos.size(), gp::polycube::kNone);
    for (std::uint32_t v = 0; v < m.pos.size(); ++v) m.origin.push_back(v);
    gp::polycube::subdivide(m);
    ASSERT_EQ(m.tri.size(), 24u);
    ASSERT_EQ(m.pos.size(), 19u);  // 7 and a midpoint for each of the 12 edges
    const auto loops = gp::polycube::boundary_loops(m.tri);
    ASSERT_EQ(loops.size(), 1u);
    ASSERT_EQ(loops[0].size(), 12u);
    for (std::size_t i = 0; i < 12; ++i) {
        const std::uint32_t v = loops[0][i];
        EXPECT_EQ(m.contour[v], 0);
        EXPECT_NEAR(m.u[v], double(i) / 12.0, 1e-12) << "loop position " << i;
        EXPECT_NEAR(glm::length(m.pos[v]), i % 2 ? std::cos(std::numbers::pi / 6.0) : 1.0, 1e-12);
    }
    for (std::uint32_t v = 7; v < 19; ++v) {
        if (std::find(loops[0].begin(), loops[0].end(), v) == loops[0].end()) {
            EXPECT_EQ(m.contour[v], -1);
        }
    }
    double area = 0.0;
    for (std::size_t f = 0; f < m.tri.size(); ++f) {
        const auto& t = m.tri[f];
        area += 0.5 * glm::length(glm::cross(m.pos[t[1]] - m.pos[t[0]], m.pos[t[2]] - m.pos[t[0]]));
        EXPECT_GE(m.tri_source[f], 11u);
        EXPECT_LE(m.tri_source[f], 16u);
    }
    EXPECT_NEAR(area, 1.5 * std::sqrt(3.0), 1e-12);  // the hexagon's

    // A square's diagonal joins two vertices of the loop, but inside: its midpoint is no loop vertex.
    gp::polycube::Local q;
    q.pos = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    q.contour = {0, 0, 0, 0};
    q.u = {0.0, 0.25, 0.5, 0.75};
    q.tri = {{0, 1, 2}, {0, 2, 3}};
    q.tri_source = {0, 1};
    q.global.assign(4, gp::polycube::kNone);
    q.origin = {0, 1, 2, 3};
    gp::polycube::subdivide(q);
    std::size_t inside = 0;
    for (std::size_t v = 4; v < q.pos.size(); ++v) {
        if (q.pos[v] == glm::dvec3(0.5, 0.5, 0.0)) {
            EXPECT_EQ(q.contour[v], -1);
            ++inside;
        }
    }
    EXPECT_EQ(inside, 1u);
    EXPECT_EQ(gp::polycube::boundary_loops(q.tri)[0].size(), 8u);
}

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/curvature.h"

#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numbers>

using namespace gimg::geo;

TEST(Curvature, FineSphereHasHOneOverRAndKOneOverRSquared) {
    const double r = 2.5;
    const Mesh sphere = gimg::geo::make_icosphere(r, 5);  // 10242 vertices, all interior
    const VertexCurvature c = compute_curvature(sphere, build_adjacency(sphere));
    double worst_h = 0.0, worst_k = 0.0;
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
        ASSERT_TRUE(c.interior[v]);
        worst_h = std::max(worst_h, std::abs(c.mean[v] * r - 1.0));
        worst_k = std::max(worst_k, std::abs(c.gaussian[v] * r * r - 1.0));
        // k1 = k2 = 1/r: k1^2 + k2^2 = 2 / r^2.
        EXPECT_NEAR(c.principal_square_sum[v] * r * r, 2.0, 0.1) << "vertex " << v;
    }
    EXPECT_LT(worst_h, 0.02);
    EXPECT_LT(worst_k, 0.02);
    std::printf("icosphere level 5: max relative error H %.4f%%, K %.4f%%\n", 100 * worst_h, 100 * worst_k);
}

TEST(Curvature, GaussBonnetAndSignFollowOrientation) {
    Mesh sphere = gimg::geo::make_uv_sphere(40, 20, 1.0);
    const MeshAdjacency adj = build_adjacency(sphere);
    const VertexCurvature c = compute_curvature(sphere, adj);
    const auto area = vertex_areas(sphere, VertexAreaKind::MixedVoronoi);
    double total = 0.0;
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) total += c.gaussian[v] * area[v];
    EXPECT_NEAR(total, 4.0 * std::numbers::pi, 1e-10);  // exact for angle defects, chi = 2
    for (double h : c.mean) EXPECT_GT(h, 0.0);

    for (auto& t : sphere.triangles) std::swap(t.y, t.z);  // normals inward
    const VertexCurvature flipped = compute_curvature(sphere, build_adjacency(sphere));
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
        EXPECT_EQ(flipped.mean[v], -c.mean[v]);
        EXPECT_EQ(flipped.gaussian[v], c.gaussian[v]);
    }
}

TEST(Curvature, FlatGridIsZeroEverywhere) {
    const Mesh grid = gimg::geo::make_grid(6, 5, 6 * 0.3, 5 * 0.3);
    const VertexCurvature c = compute_curvature(grid, build_adjacency(grid));
    for (std::size_t v = 0; v < grid.vertex_count(); ++v) {
        EXPECT_NEAR(c.mean[v], 0.0, 1e-12);
        EXPECT_NEAR(c.gaussian[v], 0.0, 1e-12);
    }
}

TEST(Curvature, BoundaryVerticesTakeTheMeanOfInteriorNeighbours) {
    // A sphere cap: faces above y = -0.3. Its rim vertices are boundary vertices.
    const Mesh full = gimg::geo::make_icosphere(1.0, 3);
    Mesh cap;
    cap.positions = full.positions;
    for (const auto& t : full.triangles)
        if ((full.positions[t.x].y + full.positions[t.y].y + full.positions[t.z].y) / 3.0 > -0.3)
            cap.triangles.push_back(t);
    const MeshAdjacency adj = build_adjacency(cap);
    const VertexCurvature c = compute_curvature(cap, adj);
    std::size_t boundary = 0, unused = 0;
    for (std::size_t v = 0; v < cap.vertex_count(); ++v) {
        if (c.interior[v]) continue;
        double h = 0.0, k = 0.0, s = 0.0;
        int n = 0;
        for (std::uint32_t j : adj.neighbors(v))
            if (c.interior[j]) {
                h += c.mean[j];
                k += c.gaussian[j];
                s += c.principal_square_sum[j];
                ++n;
            }
        if (adj.neighbors(v).empty()) {
            ++unused;
            EXPECT_EQ(c.mean[v], 0.0);
            continue;
        }
        ++boundary;
        ASSERT_GT(n, 0);
        EXPECT_DOUBLE_EQ(c.mean[v], h / n);
        EXPECT_DOUBLE_EQ(c.gaussian[v], k / n);
        EXPECT_DOUBLE_EQ(c.principal_square_sum[v], s / n);
        // And therefore close to the sphere's values.
        EXPECT_NEAR(c.mean[v], 1.0, 0.05);
    }
    EXPECT_GT(boundary, 10u);
    EXPECT_GT(unused, 10u);  // the vertices of the removed bottom
}

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/normals.h"

#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace gimg::geo;

namespace {

Mesh single_triangle(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    Mesh m;
    m.positions = {a, b, c};
    m.triangles = {{0, 1, 2}};
    return m;
}

double edge_weight(const MeshAdjacency& adj, const std::vector<double>& w, std::uint32_t a, std::uint32_t b) {
    return w[adj.find_edge(a, b)];
}

}  // namespace

TEST(Normals, FaceNormalAndAreaOfRightTriangle) {
    const Mesh m = single_triangle({0, 0, 0}, {2, 0, 0}, {0, 3, 0});
    EXPECT_EQ(face_normals(m)[0], glm::dvec3(0, 0, 1));
    EXPECT_DOUBLE_EQ(face_areas(m)[0], 3.0);
    const auto angles = corner_angles(m);
    EXPECT_DOUBLE_EQ(angles[0], std::numbers::pi / 2);
    EXPECT_NEAR(angles[1], std::atan(1.5), 1e-15);
    EXPECT_NEAR(angles[0] + angles[1] + angles[2], std::numbers::pi, 1e-15);
    // Degenerate: zero normal, zero area, angles finite.
    const Mesh d = single_triangle({0, 0, 0}, {1, 0, 0}, {2, 0, 0});
    EXPECT_EQ(face_normals(d)[0], glm::dvec3(0.0));
    EXPECT_EQ(face_areas(d)[0], 0.0);
    for (double a : corner_angles(d)) EXPECT_TRUE(std::isfinite(a));
}

TEST(Normals, AngleWeightedNormalAtBoxCornerIsTheDiagonal) {
    // Box faces are split into two triangles each; a corner lies in one or two triangles of each
    // face depending on the diagonal, and only angle weighting makes that irrelevant.
    const Mesh box = gimg::geo::make_box({2.0, 3.0, 5.0});
    const auto n = vertex_normals(box);
    for (std::size_t v = 0; v < box.vertex_count(); ++v) {
        const glm::dvec3 expected = glm::normalize(glm::sign(box.positions[v]));
        EXPECT_NEAR(glm::length(n[v] - expected), 0.0, 1e-14) << "vertex " << v;
    }
}

TEST(Normals, SphereVertexNormalsAreRadial) {
    const Mesh s = gimg::geo::make_icosphere(2.0, 3);
    const auto n = vertex_normals(s);
    for (std::size_t v = 0; v < s.vertex_count(); ++v)
        EXPECT_GT(glm::dot(n[v], glm::normalize(s.positions[v])), 0.9999);
}

TEST(Cotangent, RightAndEquilateralTriangles) {
    const Mesh right = single_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const MeshAdjacency ra = build_adjacency(right);
    const auto rw = cotangent_weights(right, ra);
    EXPECT_NEAR(edge_weight(ra, rw, 1, 2), 0.0, 1e-16);  // opposite the right angle
    EXPECT_NEAR(edge_weight(ra, rw, 0, 1), 0.5, 1e-15);  // opposite 45 degrees: cot = 1
    EXPECT_NEAR(edge_weight(ra, rw, 0, 2), 0.5, 1e-15);

    const Mesh eq = single_triangle({0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0});
    const MeshAdjacency ea = build_adjacency(eq);
    for (double w : cotangent_weights(eq, ea)) EXPECT_NEAR(w, 0.5 / std::sqrt(3.0), 1e-15);
}

TEST(Cotangent, InteriorEdgeSumsBothSidesAndObtuseGoesNegative) {
    // Edge (0,1) with apex 2 above (angle 90 deg at apex) and apex 3 below, flatter (obtuse).
    Mesh m;
    m.positions = {{-1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -0.5, 0}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}};
    const MeshAdjacency adj = build_adjacency(m);
    const auto w = cotangent_weights(m, adj);
    // Apex 3: vectors (-1, 0.5) and (1, 0.5): cot = dot/|cross| = (-1 + 0.25) / 1 = -0.75.
    EXPECT_NEAR(edge_weight(adj, w, 0, 1), 0.5 * (0.0 - 0.75), 1e-15);
}

TEST(Cotangent, DegenerateTrianglesGiveFiniteClampedWeights) {
    for (const Mesh& m : {single_triangle({0, 0, 0}, {1, 0, 0}, {2, 0, 0}),  // collinear
                          single_triangle({0, 0, 0}, {0, 0, 0}, {1, 0, 0}),  // two corners equal
                          single_triangle({0, 0, 0}, {0, 0, 0}, {0, 0, 0}),  // a point
                          single_triangle({0, 0, 0}, {1, 0, 0}, {0.5, 1e-300, 0})}) {
        const auto w = cotangent_weights(m, build_adjacency(m));
        for (double x : w) {
            EXPECT_TRUE(std::isfinite(x));
            EXPECT_LE(std::abs(x), 1.5 * kMaxCotangent);
        }
        for (auto kind : {VertexAreaKind::Barycentric, VertexAreaKind::MixedVoronoi})
            for (double a : vertex_areas(m, kind)) EXPECT_TRUE(std::isfinite(a));
    }
    // The collinear triangle's angle of pi at corner 1 has cotangent -infinity, clamped.
    EXPECT_EQ(clamped_cotangent({-1, 0, 0}, {1, 0, 0}), -kMaxCotangent);
    EXPECT_EQ(clamped_cotangent({1, 0, 0}, {2, 0, 0}), kMaxCotangent);
    EXPECT_EQ(clamped_cotangent({0, 0, 0}, {1, 0, 0}), 0.0);
}

TEST(VertexAreas, RightAndObtuseTriangles) {
    const Mesh right = single_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const auto bary = vertex_areas(right, VertexAreaKind::Barycentric);
    for (double a : bary) EXPECT_NEAR(a, 0.5 / 3.0, 1e-16);
    // Voronoi regions: the circumcentre is the hypotenuse midpoint (0.5, 0.5); the right-angle
    // corner owns the square [0, 0.5]^2, the others a quarter-triangle of area 1/8 each.
    const auto mixed = vertex_areas(right, VertexAreaKind::MixedVoronoi);
    EXPECT_NEAR(mixed[0], 0.25, 1e-16);
    EXPECT_NEAR(mixed[1], 0.125, 1e-16);
    EXPECT_NEAR(mixed[2], 0.125, 1e-16);

    const Mesh obtuse = single_triangle({0, 0, 0}, {2, 0, 0}, {1, 0.2, 0});  // obtuse at corner 2
    const auto mo = vertex_areas(obtuse, VertexAreaKind::MixedVoronoi);
    EXPECT_NEAR(mo[2], 0.1, 1e-16);
    EXPECT_NEAR(mo[0], 0.05, 1e-16);
    EXPECT_NEAR(mo[1], 0.05, 1e-16);
}

TEST(VertexAreas, TileTheSurface) {
    Mesh m = gimg::geo::make_uv_sphere(24, 12, 1.5);  // obtuse triangles near the poles
    double total = 0.0;
    for (double a : face_areas(m)) total += a;
    for (auto kind : {VertexAreaKind::Barycentric, VertexAreaKind::MixedVoronoi}) {
        double sum = 0.0;
        for (double a : vertex_areas(m, kind)) {
            EXPECT_GT(a, 0.0);
            sum += a;
        }
        EXPECT_NEAR(sum, total, 1e-12 * total);
    }
}

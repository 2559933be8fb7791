// analyze_topology on shapes whose answers are known by construction: closed and open surfaces of
// known genus, a non-orientable strip, and each defect on its own.
#include "gimg/geometry/error.h"
#include "gimg/geometry/topology.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using gimg::geo::analyze_topology;
using gimg::geo::Mesh;
using gimg::geo::MeshInfo;

namespace {

constexpr double kPi = 3.14159265358979323846;

Mesh tetrahedron() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

// Two triangles per quad of a grid of columns x rows vertices. wrap_columns glues the last column
// to the first (twisted: upside down, for a Moebius strip); wrap_rows glues the last row to the first.
Mesh grid(int columns, int rows, bool wrap_columns, bool twisted, bool wrap_rows) {
    Mesh m;
    for (int i = 0; i < columns; ++i) {
        for (int j = 0; j < rows; ++j) {
            const double u = 2 * kPi * i / columns, v = 2 * kPi * j / rows;
            m.positions.emplace_back((2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v));
        }
    }
    auto id = [&](int i, int j) -> unsigned {
        if (i == columns) {
            i = 0;
            if (twisted) j = rows - 1 - j;
        }
        if (j == rows) j = 0;
        return static_cast<unsigned>(i * rows + j);
    };
    for (int i = 0; i < (wrap_columns ? columns : columns - 1); ++i) {
        for (int j = 0; j < (wrap_rows ? rows : rows - 1); ++j) {
            const unsigned a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            m.triangles.emplace_back(a, b, c);
            m.triangles.emplace_back(a, c, d);
        }
    }
    return m;
}

Mesh single_triangle() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    return m;
}

}  // namespace

TEST(Topology, TetrahedronIsAClosedSphere) {
    const MeshInfo info = analyze_topology(tetrahedron());
    EXPECT_EQ(info.vertices, 4u);
    EXPECT_EQ(info.faces, 4u);
    EXPECT_EQ(info.edges, 6u);
    EXPECT_EQ(info.components, 1u);
    EXPECT_EQ(info.boundary_loops, 0u);
    EXPECT_TRUE(info.closed && info.manifold && info.orientable && info.oriented);
    ASSERT_EQ(info.component_info.size(), 1u);
    EXPECT_EQ(info.component_info[0].euler_characteristic, 2);
    EXPECT_EQ(info.component_info[0].genus, 0);
    EXPECT_EQ(info.bbox.min, glm::dvec3(0, 0, 0));
    EXPECT_EQ(info.bbox.max, glm::dvec3(1, 1, 1));
}

TEST(Topology, TriangleIsADisk) {
    const MeshInfo info = analyze_topology(single_triangle());
    EXPECT_EQ(info.edges, 3u);
    EXPECT_EQ(info.boundary_edges, 3u);
    EXPECT_EQ(info.boundary_loops, 1u);
    EXPECT_FALSE(info.closed);
    EXPECT_EQ(info.component_info[0].genus, 0);
}

TEST(Topology, TorusHasGenusOne) {
    const MeshInfo info = analyze_topology(grid(8, 5, true, false, true));
    EXPECT_EQ(info.vertices, 40u);
    EXPECT_EQ(info.faces, 80u);
    EXPECT_EQ(info.edges, 120u);
    EXPECT_TRUE(info.closed && info.manifold && info.oriented);
    EXPECT_EQ(info.component_info[0].euler_characteristic, 0);
    EXPECT_EQ(info.component_info[0].genus, 1);
}

TEST(Topology, AnnulusHasTwoBoundaryLoopsAndGenusZero) {
    const MeshInfo info = analyze_topology(grid(10, 2, true, false, false));
    EXPECT_EQ(info.boundary_loops, 2u);
    EXPECT_EQ(info.boundary_edges, 20u);
    EXPECT_EQ(info.component_info[0].genus, 0);
}

TEST(Topology, MoebiusStripIsNotOrientable) {
    const MeshInfo info = analyze_topology(grid(9, 2, true, true, false));
    EXPECT_EQ(info.boundary_loops, 1u);  // the famous single edge
    EXPECT_TRUE(info.manifold);
    EXPECT_FALSE(info.orientable);
    EXPECT_FALSE(info.oriented);
    EXPECT_GT(info.inconsistent_edges, 0u);
    EXPECT_FALSE(info.component_info[0].genus.has_value());
}

TEST(Topology, FlippedFaceIsOrientableButNotOriented) {
    Mesh m = tetrahedron();
    std::swap(m.triangles[3][1], m.triangles[3][2]);
    const MeshInfo info = analyze_topology(m);
    EXPECT_TRUE(info.orientable);
    EXPECT_FALSE(info.oriented);
    EXPECT_EQ(info.inconsistent_edges, 3u);
    EXPECT_EQ(info.component_info[0].genus, 0);  // orientation does not change the topology
}

TEST(Topology, ThreeFacesOnAnEdgeMakeANonManifoldEdge) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const MeshInfo info = analyze_topology(m);
    EXPECT_EQ(info.non_manifold_edges, 1u);
    EXPECT_EQ(info.non_manifold_vertices, 0u);  // the fans at 0 and 1 are joined through the edge
    EXPECT_EQ(info.components, 1u);
    EXPECT_FALSE(info.manifold);
    EXPECT_FALSE(info.component_info[0].genus.has_value());
}

TEST(Topology, BowtieHasANonManifoldVertexAndTwoLoops) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    m.triangles = {{0, 1, 2}, {0, 3, 4}};
    const MeshInfo info = analyze_topology(m);
    EXPECT_EQ(info.non_manifold_vertices, 1u);
    EXPECT_EQ(info.components, 1u);  // joined by the shared vertex
    EXPECT_EQ(info.boundary_loops, 2u);
    EXPECT_FALSE(info.component_info[0].genus.has_value());
}

TEST(Topology, TwoClosedSurfacesTouchingAtAVertex) {
    Mesh m = tetrahedron();
    const Mesh t = tetrahedron();
    for (const glm::dvec3& p : t.positions) {
        if (p != glm::dvec3(0)) m.positions.push_back(-p);  // share vertex 0
    }
    for (glm::uvec3 f : t.triangles) {
        for (int k = 0; k < 3; ++k) f[k] = f[k] == 0 ? 0 : f[k] + 3;
        m.triangles.push_back(f);
    }
    const MeshInfo info = analyze_topology(m);
    EXPECT_EQ(info.non_manifold_vertices, 1u);
    EXPECT_EQ(info.components, 1u);
    EXPECT_TRUE(info.closed);
    EXPECT_EQ(info.boundary_loops, 0u);
}

TEST(Topology, DuplicateCollapsedAndZeroAreaFaces) {
    Mesh m = tetrahedron();
    m.triangles.push_back({2, 1, 0});  // the first face again, reversed
    m.triangles.push_back({0, 0, 1});  // collapsed
    m.positions.push_back({2, 0, 0});  // on the line through 0 and 1
    m.triangles.push_back({0, 1, 4});  // zero area
    const MeshInfo info = analyze_topology(m);
    EXPECT_EQ(info.duplicate_faces, 1u);
    EXPECT_EQ(info.collapsed_faces, 1u);
    EXPECT_EQ(info.zero_area_faces, 1u);
    EXPECT_EQ(info.degenerate_faces, 2u);
    EXPECT_EQ(info.faces, 7u);
    // The duplicate puts a third face on each of its edges; the zero-area face a fourth on 0-1.
    EXPECT_EQ(info.non_manifold_edges, 3u);
    EXPECT_EQ(info.edges, 8u);  // 6 + the zero-area face's 0-4 and 1-4; the collapsed one adds none
}

TEST(Topology, IsolatedAndNonFiniteVertices) {
    Mesh m = single_triangle();
    m.positions.push_back({5, 5, 5});  // in no face
    m.positions.push_back({std::numeric_limits<double>::quiet_NaN(), 0, 0});
    const MeshInfo info = analyze_topology(m);
    EXPECT_EQ(info.isolated_vertices, 2u);
    EXPECT_EQ(info.nonfinite_vertices, 1u);
    EXPECT_EQ(info.components, 1u);
    EXPECT_EQ(info.bbox.max, glm::dvec3(5, 5, 5));  // the NaN vertex is left out
}

TEST(Topology, ComponentsLargestFirst) {
    Mesh m = single_triangle();
    const Mesh torus = grid(6, 4, true, false, true);
    const auto offset = static_cast<unsigned>(m.positions.size());
    m.positions.insert(m.positions.end(), torus.positions.begin(), torus.positions.end());
    for (const glm::uvec3& t : torus.triangles) m.triangles.push_back(t + offset);
    const MeshInfo info = analyze_topology(m);
    ASSERT_EQ(info.components, 2u);
    EXPECT_EQ(info.component_info[0].faces, torus.triangles.size());
    EXPECT_EQ(info.component_info[0].genus, 1);
    EXPECT_EQ(info.component_info[1].faces, 1u);
    EXPECT_EQ(info.component_info[1].genus, 0);
    EXPECT_EQ(info.component_info[1].boundary_loops, 1u);
}

TEST(Topology, IndexOutOfRangeIsAnInputError) {
    Mesh m = single_triangle();
    m.triangles.push_back({0, 1, 3});
    EXPECT_THROW(analyze_topology(m), gimg::geo::InputError);
}

TEST(Topology, EmptyMesh) {
    const MeshInfo info = analyze_topology(Mesh{});
    EXPECT_EQ(info.components, 0u);
    EXPECT_EQ(info.edges, 0u);
    EXPECT_TRUE(info.closed);
}

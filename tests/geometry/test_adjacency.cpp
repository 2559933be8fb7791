#include "gimg/geometry/adjacency.h"

#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

using gimg::geo::build_adjacency;
using gimg::geo::kInvalidIndex;
using gimg::geo::Mesh;
using gimg::geo::MeshAdjacency;
using U = std::vector<std::uint32_t>;

namespace {

// Two triangles sharing edge (1, 2), plus a third triangle on that same edge (a non-manifold
// fin), plus an isolated vertex 5.
Mesh fin_mesh() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 1}, {9, 9, 9}};
    m.triangles = {{0, 1, 2}, {1, 3, 2}, {2, 1, 4}};
    return m;
}

}  // namespace

TEST(Adjacency, KnownSmallMeshCsrArrays) {
    const MeshAdjacency adj = build_adjacency(fin_mesh());
    EXPECT_EQ(adj.vertex_count(), 6u);
    EXPECT_EQ(adj.vertex_vertex_offsets, (U{0, 2, 6, 10, 12, 14, 14}));
    EXPECT_EQ(adj.vertex_vertices, (U{1, 2, /*1*/ 0, 2, 3, 4, /*2*/ 0, 1, 3, 4, /*3*/ 1, 2, /*4*/ 1, 2}));
    EXPECT_EQ(adj.vertex_face_offsets, (U{0, 1, 4, 7, 8, 9, 9}));
    EXPECT_EQ(adj.vertex_faces, (U{0, /*1*/ 0, 1, 2, /*2*/ 0, 1, 2, /*3*/ 1, /*4*/ 2}));
    EXPECT_EQ(adj.edges, (U{0, 1, 0, 2, 1, 2, 1, 3, 1, 4, 2, 3, 2, 4}));
    EXPECT_EQ(adj.edge_face_offsets, (U{0, 1, 2, 5, 6, 7, 8, 9}));
    EXPECT_EQ(adj.edge_faces, (U{0, 0, /*1-2*/ 0, 1, 2, 1, 2, 1, 2}));
    // Face 0 = (0,1,2): sides (0,1), (1,2), (2,0) -> edges 0, 2, 1.
    EXPECT_EQ(adj.face_edges, (U{0, 2, 1, /*(1,3,2)*/ 3, 5, 2, /*(2,1,4)*/ 2, 4, 6}));
    EXPECT_EQ(adj.find_edge(2, 1), 2u);
    EXPECT_EQ(adj.find_edge(4, 2), 6u);
    EXPECT_EQ(adj.find_edge(0, 3), kInvalidIndex);
    EXPECT_EQ(adj.find_edge(5, 5), kInvalidIndex);
    // Nothing here is interior: every vertex touches a boundary or the 3-face edge, 5 is isolated.
    EXPECT_EQ(adj.interior_vertices(), (std::vector<std::uint8_t>(6, 0)));
}

TEST(Adjacency, DegenerateFaceRepeatingAVertex) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 0, 1}};
    const MeshAdjacency adj = build_adjacency(m);
    EXPECT_EQ(adj.edges, (U{0, 1, 0, 2, 1, 2}));
    EXPECT_EQ(adj.edge_faces, (U{0, 1, 0, 0}));  // edge (0,1): faces 0 and 1, face 1 listed once
    EXPECT_EQ(adj.face_edges, (U{0, 2, 1, kInvalidIndex, 0, 0}));
    EXPECT_EQ(adj.vertex_faces, (U{0, 1, 0, 1, 0}));
    EXPECT_EQ(adj.neighbors(0).size(), 2u);
}

TEST(Adjacency, RejectsOutOfRangeIndex) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 3}};
    EXPECT_THROW(build_adjacency(m), std::invalid_argument);
}

TEST(Adjacency, ClosedIcosphereMatchesEulerAndIsSymmetric) {
    const Mesh m = gimg::geo::make_icosphere(1.0, 3);
    const MeshAdjacency adj = build_adjacency(m);
    const std::size_t v = m.vertex_count(), e = adj.edge_count(), f = m.face_count();
    EXPECT_EQ(long(v) - long(e) + long(f), 2);  // sphere
    EXPECT_EQ(2 * e, 3 * f);
    std::set<std::pair<std::uint32_t, std::uint32_t>> expected;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) expected.insert(std::minmax(t[k], t[(k + 1) % 3]));
    ASSERT_EQ(expected.size(), e);
    std::size_t i = 0;
    for (const auto& [a, b] : expected) {  // std::set order is the lexicographic order
        EXPECT_EQ(adj.edges[2 * i], a);
        EXPECT_EQ(adj.edges[2 * i + 1], b);
        EXPECT_EQ(adj.edge_face_count(i), 2u);
        ++i;
    }
    for (std::uint32_t a = 0; a < v; ++a) {
        const auto nb = adj.neighbors(a);
        EXPECT_TRUE(std::is_sorted(nb.begin(), nb.end()));
        EXPECT_TRUE(std::adjacent_find(nb.begin(), nb.end()) == nb.end());
        for (std::uint32_t b : nb) {
            const auto back = adj.neighbors(b);
            EXPECT_TRUE(std::binary_search(back.begin(), back.end(), a));
        }
        EXPECT_EQ(nb.size(), adj.faces_of_vertex(a).size());  // closed fan: degree = faces
    }
    for (std::size_t face = 0; face < f; ++face)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t edge = adj.face_edges[3 * face + k];
            EXPECT_EQ(edge, adj.find_edge(m.triangles[face][k], m.triangles[face][(k + 1) % 3]));
            const auto faces = adj.faces_of_edge(edge);
            EXPECT_TRUE(std::find(faces.begin(), faces.end(), face) != faces.end());
        }
    const auto interior = adj.interior_vertices();
    EXPECT_EQ(std::count(interior.begin(), interior.end(), 1), long(v));
}

TEST(Adjacency, InteriorVerticesOfGridAndBowtie) {
    const Mesh grid = gimg::geo::make_grid(3, 2, 3, 2);
    const auto interior = build_adjacency(grid).interior_vertices();
    // Only the two grid points off the border, (1,1) and (2,1), are interior.
    std::vector<std::uint8_t> expected(12, 0);
    expected[5] = expected[6] = 1;
    EXPECT_EQ(interior, expected);

    // Two closed octahedra sharing one vertex: every edge has two faces, but the shared vertex
    // has two fans and is not interior.
    Mesh bowtie;
    // Octahedron around c; corner `shared` (if any) reuses vertex `shared_with`.
    auto add_octahedron = [&](glm::dvec3 c, int shared, std::uint32_t shared_with) {
        const glm::dvec3 dirs[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
        std::uint32_t id[6];
        for (int i = 0; i < 6; ++i) {
            if (i == shared) {
                id[i] = shared_with;
                continue;
            }
            id[i] = static_cast<std::uint32_t>(bowtie.positions.size());
            bowtie.positions.push_back(c + dirs[i]);
        }
        for (int x : {0, 1})
            for (int y : {2, 3})
                for (int z : {4, 5}) bowtie.triangles.push_back({id[x], id[y], id[z]});
    };
    add_octahedron({0, 0, 0}, -1, 0);  // vertex 0 at (-1, 0, 0)
    add_octahedron({-2, 0, 0}, 1, 0);  // its +x corner is that same point
    const MeshAdjacency adj = build_adjacency(bowtie);
    for (std::size_t e = 0; e < adj.edge_count(); ++e) EXPECT_EQ(adj.edge_face_count(e), 2u);
    const auto in = adj.interior_vertices();
    EXPECT_EQ(in[0], 0);
    EXPECT_EQ(std::count(in.begin(), in.end(), 1), long(bowtie.vertex_count()) - 1);
}

// Spatial vertex renumbering: the same surface, neighbours close in number.
#include "gimg/geometry/parallel_for.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/vertex_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

using namespace gimg::geo;

namespace {

// Mean |i - j| over the triangles' edges.
double mean_edge_index_distance(const Mesh& m) {
    double sum = 0.0;
    for (const glm::uvec3& t : m.triangles)
        sum += std::abs(double(t.x) - t.y) + std::abs(double(t.y) - t.z) + std::abs(double(t.z) - t.x);
    return sum / (3.0 * double(m.face_count()));
}

}  // namespace

TEST(VertexOrder, IsAPermutation) {
    const Mesh m = make_icosphere(1.0, 4);
    std::vector<std::uint32_t> order = spatial_vertex_order(m);
    ASSERT_EQ(order.size(), m.vertex_count());
    std::sort(order.begin(), order.end());
    std::vector<std::uint32_t> identity(m.vertex_count());
    std::iota(identity.begin(), identity.end(), 0u);
    EXPECT_EQ(order, identity);
}

TEST(VertexOrder, KeepsTheSurfaceAndItsAttributes) {
    Mesh m = make_icosphere(1.0, 3);
    m.texcoords.resize(m.vertex_count());
    m.normals.resize(m.vertex_count());
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        m.texcoords[v] = {double(v), -double(v)};
        m.normals[v] = m.positions[v];
    }
    const std::vector<std::uint32_t> order = spatial_vertex_order(m);
    const Mesh r = reorder_vertices(m, order);
    ASSERT_EQ(r.vertex_count(), m.vertex_count());
    ASSERT_EQ(r.face_count(), m.face_count());
    // Triangle f has the same corners, in the same order, as before.
    for (std::size_t f = 0; f < m.face_count(); ++f)
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(r.positions[r.triangles[f][c]], m.positions[m.triangles[f][c]]);
            EXPECT_EQ(r.texcoords[r.triangles[f][c]], m.texcoords[m.triangles[f][c]]);
            EXPECT_EQ(r.normals[r.triangles[f][c]], m.normals[m.triangles[f][c]]);
        }
    // Values of the reordered mesh return to the original numbering.
    EXPECT_EQ(original_vertex_order(r.positions, order), m.positions);
}

TEST(VertexOrder, BringsNeighboursTogether) {
    // An icosphere numbers each subdivision's new vertices after the old ones, like
    // armadillo_loop1: neighbours far apart in number.
    const Mesh m = make_icosphere(1.0, 6);
    const Mesh r = reorder_vertices(m, spatial_vertex_order(m));
    const double before = mean_edge_index_distance(m), after = mean_edge_index_distance(r);
    EXPECT_GT(before, 5000.0);
    EXPECT_LT(after, before / 10.0);
}

TEST(VertexOrder, FlatAndEmptyMeshes) {
    EXPECT_TRUE(spatial_vertex_order(Mesh{}).empty());
    const Mesh grid = make_grid(4, 3);  // z = 0 everywhere: one axis has no extent
    const std::vector<std::uint32_t> order = spatial_vertex_order(grid);
    EXPECT_EQ(order.size(), grid.vertex_count());
    EXPECT_EQ(reorder_vertices(grid, order).face_count(), grid.face_count());
}

TEST(VertexOrder, MortonOrderOfTheCubesCornersIsTheZCurve) {
    // Corner (x, y, z) of the unit cube is number x + 2y + 4z along the curve (x the lowest bit),
    // whatever order the points come in; a repeated point keeps its place after the first.
    std::vector<glm::dvec3> points;
    for (int k : {6, 1, 7, 0, 3, 5, 2, 4}) points.push_back(glm::dvec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
    points.push_back({1.0, 1.0, 1.0});
    const std::vector<std::uint32_t> order = morton_order(points);
    EXPECT_EQ(order, (std::vector<std::uint32_t>{3, 1, 6, 4, 7, 5, 0, 2, 8}));
}

TEST(VertexOrder, LargeMortonOrderIsAStableSortByKeyOnAnyThreadCount) {
    // 300,000 points on the 128^3 lattice of 7 bits an axis (many repeated, so ties matter), sorted
    // by the sort in chunks on every core: the same order as a stable sort by the interleaved bits,
    // with 1 thread or 5.
    std::vector<glm::dvec3> points;
    std::uint64_t state = 12345;
    auto next = [&state] { return (state = state * 6364136223846793005ull + 1442695040888963407ull) >> 57; };
    for (int i = 0; i < 300000; ++i) points.push_back(glm::dvec3(double(next()), double(next()), double(next())));
    points.push_back({0.0, 0.0, 0.0});  // the lattice's corners, so each axis spans 0..127 exactly
    points.push_back({127.0, 127.0, 127.0});
    auto key = [](const glm::dvec3& p) {
        std::uint64_t k = 0;
        for (int bit = 0; bit < 7; ++bit)
            for (int axis = 0; axis < 3; ++axis) k |= ((std::uint64_t(p[axis]) >> bit) & 1u) << (3 * bit + axis);
        return k;
    };
    std::vector<std::uint32_t> expected(points.size());
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key(points[a]) < key(points[b]); });
    for (unsigned threads : {1u, 5u}) {
        set_default_thread_count(threads);
        EXPECT_EQ(morton_order(points, 7), expected) << threads << " threads";
    }
    set_default_thread_count(0);
}

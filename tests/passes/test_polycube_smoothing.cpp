// The polycube map's chart smoothing (step 5): away from turned triangles a move must not raise the
// distortion of the triangles around the vertex, so an undistorted map stays as it is, and a
// distorted one only improves.
#include "polycube/polycube_parts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace gimg;
namespace gp = gimg::passes;

namespace {

constexpr std::uint8_t kPlusZ = 4;  // the axis index of a polycube face facing +z

// An n x n grid over the unit square in the plane z = 0, counter-clockwise seen from +z, its
// interior vertices moved by up to `jitter` of a cell (a fixed pattern) so that some triangles
// are obtuse.
geo::Mesh planar_grid(int n, double jitter) {
    geo::Mesh m;
    const double h = 1.0 / (n - 1);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            glm::dvec3 p(i * h, j * h, 0.0);
            if (i > 0 && j > 0 && i < n - 1 && j < n - 1)
                p += jitter * h *
                     glm::dvec3(std::sin(12.9898 * i + 78.233 * j), std::cos(39.3468 * i + 11.135 * j), 0.0);
            m.positions.push_back(p);
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const auto v = std::uint32_t(j * n + i);
            m.triangles.push_back({v, v + 1, v + std::uint32_t(n) + 1});
            m.triangles.push_back({v, v + std::uint32_t(n) + 1, v + std::uint32_t(n)});
        }
    return m;
}

// The polycube face under the grid: a square in z = 0 facing +z.
geo::Mesh plane_face() {
    geo::Mesh m;
    m.positions = {{-1, -1, 0}, {2, -1, 0}, {2, 2, 0}, {-1, 2, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

gp::polycube::SlicedMesh uncut(const geo::Mesh& mesh) {
    gp::polycube::SlicedMesh s{mesh, {}, std::vector<std::int32_t>(mesh.vertex_count(), -1)};
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) s.source_face.push_back(f);
    return s;
}

// The area-weighted sum of triangle_distortion, the images scaled by `scale`.
double total_distortion(const geo::Mesh& mesh, const std::vector<glm::dvec3>& image, double scale) {
    double sum = 0.0;
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::dvec3 a[3] = {mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]};
        const glm::dvec3 b[3] = {scale * image[t[0]], scale * image[t[1]], scale * image[t[2]]};
        const auto [area, angle] = gp::polycube::triangle_distortion(a, b);
        sum += glm::length(glm::cross(a[1] - a[0], a[2] - a[0])) * (area + angle);
    }
    return sum;
}

std::size_t turned_count(const geo::Mesh& mesh, const std::vector<glm::dvec3>& image,
                         const std::vector<std::uint8_t>& axis) {
    std::size_t n = 0;
    for (const glm::uvec3& t : mesh.triangles) n += gp::polycube::turned(t, image, axis);
    return n;
}

}  // namespace

// The identity map of a planar mesh with obtuse triangles: the clamped cotangent weights do not
// reproduce it (the harmonic mean of some vertex lies elsewhere, so keeping every move would move
// it), but nothing is turned, and no move can lower the distortion below the identity's: the
// smoothing keeps every image where it is (keeping every move would move one by more than 1e-3).
TEST(PolycubeChartSmoothing, KeepsAnUndistortedMap) {
    const geo::Mesh mesh = planar_grid(9, 0.35);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const std::vector<double> w = gp::polycube::positive_cotangent_weights(mesh, adj);
    double farthest = 0.0;
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
        glm::dvec3 sum(0.0);
        double total = 0.0;
        for (std::uint32_t k = adj.vertex_vertex_offsets[v]; k < adj.vertex_vertex_offsets[v + 1]; ++k) {
            const std::uint32_t u = adj.vertex_vertices[k];
            sum += w[adj.find_edge(v, u)] * mesh.positions[u];
            total += w[adj.find_edge(v, u)];
        }
        farthest = std::max(farthest, glm::length(sum / total - mesh.positions[v]));
    }
    ASSERT_GT(farthest, 1e-3);

    std::vector<glm::dvec3> image = mesh.positions;
    std::vector<std::uint8_t> axis(mesh.vertex_count(), kPlusZ);
    ASSERT_EQ(turned_count(mesh, image, axis), 0u);
    gp::polycube::smooth_map(uncut(mesh), mesh.positions, mesh.face_count(), plane_face(), {kPlusZ, kPlusZ}, image,
                             axis, 10);
    // (A vertex whose mean is its own position may move by a rounding step.)
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
        ASSERT_LT(glm::length(image[v] - mesh.positions[v]), 1e-12) << v;
}

// A regular grid mapped onto a jittered copy of itself: the smoothing moves images, turns nothing,
// and the distortion (at the scale it measures with) falls.
TEST(PolycubeChartSmoothing, LowersTheDistortionOfAnUntangledMap) {
    const geo::Mesh mesh = planar_grid(9, 0.0);
    std::vector<glm::dvec3> image = planar_grid(9, 0.35).positions;
    std::vector<std::uint8_t> axis(mesh.vertex_count(), kPlusZ);
    ASSERT_EQ(turned_count(mesh, image, axis), 0u);
    const double before = total_distortion(mesh, image, 1.0);  // both cover the unit square
    const std::size_t moves = gp::polycube::smooth_map(uncut(mesh), mesh.positions, mesh.face_count(), plane_face(),
                                                       {kPlusZ, kPlusZ}, image, axis, 10);
    EXPECT_GT(moves, 0u);
    EXPECT_EQ(turned_count(mesh, image, axis), 0u);
    const double after = total_distortion(mesh, image, 1.0);
    EXPECT_LT(after, 0.9 * before) << before << " -> " << after;
    EXPECT_GE(after, 2.0 * 2.0 - 1e-12);  // every triangle's sum is at least 2; the doubled areas sum to 2
}

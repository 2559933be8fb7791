// Cutting meshes open into disks: the cut graph's topology on a disk, a sphere, a torus and an
// annulus, the seam, shortest paths, opening along a cut and splitting the edges that join two
// boundary vertices.
#include "gimg/geometry/disk_cut.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/topology.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <set>

using namespace gimg;

namespace {

std::size_t count(const std::vector<std::uint8_t>& flags) {
    return std::size_t(std::count(flags.begin(), flags.end(), 1));
}

// Vertices touched by the cut's edges (boundary edges not counted).
std::size_t cut_vertex_count(const geo::MeshAdjacency& adj, const std::vector<std::uint8_t>& cut) {
    std::set<std::uint32_t> v;
    for (std::size_t e = 0; e < cut.size(); ++e)
        if (cut[e]) v.insert(adj.edges[2 * e]), v.insert(adj.edges[2 * e + 1]);
    return v.size();
}

// One component, one boundary loop, Euler characteristic 1, manifold: a disk.
void expect_disk(const geo::Mesh& m, const char* what) {
    const geo::MeshInfo info = geo::analyze_topology(m);
    EXPECT_EQ(info.components, 1u) << what;
    EXPECT_EQ(info.boundary_loops, 1u) << what;
    EXPECT_TRUE(info.manifold) << what;
    EXPECT_TRUE(info.oriented) << what;
    ASSERT_FALSE(info.component_info.empty()) << what;
    EXPECT_EQ(info.component_info[0].euler_characteristic, 1) << what;
}

// Every face of the opened mesh sits where the original's does, corner for corner.
void expect_same_surface(const geo::Mesh& mesh, const geo::OpenedMesh& o) {
    ASSERT_EQ(o.disk.face_count(), mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(o.source[o.disk.triangles[f][k]], mesh.triangles[f][k]);
            EXPECT_EQ(o.disk.positions[o.disk.triangles[f][k]], mesh.positions[mesh.triangles[f][k]]);
        }
}

geo::Mesh annulus() {
    geo::Mesh m = geo::make_grid(7, 7);  // without its middle cell
    std::erase_if(m.triangles, [&](const glm::uvec3& t) {
        const glm::dvec3 c = (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0;
        return std::abs(c.x - 0.5) < 0.07 && std::abs(c.y - 0.5) < 0.07;
    });
    return m;
}

}  // namespace

TEST(DiskCut, ADiskNeedsNoCut) {
    const geo::Mesh grid = geo::make_grid(6, 5);
    const geo::MeshAdjacency adj = geo::build_adjacency(grid);
    const auto cut = geo::initial_cut(grid, adj);
    EXPECT_EQ(count(cut), 0u);
    const geo::OpenedMesh o = geo::open_along(grid, adj, cut);
    EXPECT_EQ(o.disk.vertex_count(), grid.vertex_count());
    expect_same_surface(grid, o);
    // The texture coordinates travel with their vertices.
    ASSERT_TRUE(o.disk.has_texcoords());
    for (std::size_t v = 0; v < o.disk.vertex_count(); ++v) EXPECT_EQ(o.disk.texcoords[v], grid.texcoords[o.source[v]]);
}

TEST(DiskCut, AClosedSphereNeedsASeamBetweenFarPoints) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 2);
    const geo::MeshAdjacency adj = geo::build_adjacency(sphere);
    auto cut = geo::initial_cut(sphere, adj);
    EXPECT_EQ(count(cut), 0u);  // a tree of faces on a sphere leaves a tree of edges: pruned to nothing
    const std::size_t edges = geo::add_seam(sphere, adj, cut);
    ASSERT_GE(edges, 2u);
    EXPECT_EQ(count(cut), edges);
    EXPECT_EQ(cut_vertex_count(adj, cut), edges + 1);  // a path
    // Its ends: the two vertices of the path with one cut edge, nearly antipodal.
    std::vector<int> degree(sphere.vertex_count(), 0);
    for (std::size_t e = 0; e < cut.size(); ++e)
        if (cut[e]) ++degree[adj.edges[2 * e]], ++degree[adj.edges[2 * e + 1]];
    std::vector<glm::dvec3> ends;
    for (std::size_t v = 0; v < degree.size(); ++v)
        if (degree[v] == 1) ends.push_back(sphere.positions[v]);
    ASSERT_EQ(ends.size(), 2u);
    EXPECT_GT(glm::distance(ends[0], ends[1]), 1.9);
    const geo::OpenedMesh o = geo::open_along(sphere, adj, cut);
    expect_disk(o.disk, "sphere");
    expect_same_surface(sphere, o);
    EXPECT_EQ(o.disk.vertex_count(), sphere.vertex_count() + edges - 1);  // the path's inner vertices twice
}

TEST(DiskCut, ATetrahedronsSeamHasTwoEdges) {
    geo::Mesh tetra;
    tetra.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const geo::MeshAdjacency adj = geo::build_adjacency(tetra);
    auto cut = geo::initial_cut(tetra, adj);
    EXPECT_EQ(geo::add_seam(tetra, adj, cut), 2u);  // one edge would open nothing
    expect_disk(geo::open_along(tetra, adj, cut).disk, "tetrahedron");
}

TEST(DiskCut, ATorusIsCutAlongTwoLoops) {
    const geo::Mesh torus = geo::make_torus(2.0, 0.6, 24, 10);
    const geo::MeshAdjacency adj = geo::build_adjacency(torus);
    const auto cut = geo::initial_cut(torus, adj);
    // A cut graph of a closed genus-g surface has Euler characteristic 1 - 2g: edges - vertices = 1.
    EXPECT_EQ(double(count(cut)) - double(cut_vertex_count(adj, cut)), 1.0);
    const geo::OpenedMesh o = geo::open_along(torus, adj, cut);
    expect_disk(o.disk, "torus");
    expect_same_surface(torus, o);
}

TEST(DiskCut, TheHolesOfAnAnnulusAreJoinedByAPath) {
    const geo::Mesh ring = annulus();
    ASSERT_EQ(geo::analyze_topology(ring).boundary_loops, 2u);
    const geo::MeshAdjacency adj = geo::build_adjacency(ring);
    const auto cut = geo::initial_cut(ring, adj);
    ASSERT_GT(count(cut), 0u);
    EXPECT_EQ(cut_vertex_count(adj, cut), count(cut) + 1);  // one path, from loop to loop
    const geo::OpenedMesh o = geo::open_along(ring, adj, cut);
    expect_disk(o.disk, "annulus");
    expect_same_surface(ring, o);
}

TEST(DiskCut, ShortestPathsAreShortestAndLeadBack) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 2);
    const geo::MeshAdjacency adj = geo::build_adjacency(sphere);
    std::vector<std::uint8_t> sources(sphere.vertex_count(), 0);
    sources[5] = sources[100] = 1;
    const geo::PathTree t = geo::shortest_paths(sphere, adj, sources);
    EXPECT_EQ(t.distance[5], 0.0);
    EXPECT_EQ(t.distance[100], 0.0);
    for (std::size_t e = 0; e < adj.edge_count(); ++e) {
        const std::uint32_t a = adj.edges[2 * e], b = adj.edges[2 * e + 1];
        EXPECT_LE(std::abs(t.distance[a] - t.distance[b]),
                  glm::distance(sphere.positions[a], sphere.positions[b]) + 1e-12);
    }
    for (std::uint32_t v = 0; v < sphere.vertex_count(); ++v) {
        if (sources[v]) continue;
        const std::uint32_t p = t.previous[v];
        ASSERT_NE(p, geo::kInvalidIndex);
        EXPECT_NEAR(t.distance[v], t.distance[p] + glm::distance(sphere.positions[v], sphere.positions[p]), 1e-12);
    }
    // A path from the vertex farthest from both sources reaches one of them.
    const auto far = std::uint32_t(std::max_element(t.distance.begin(), t.distance.end()) - t.distance.begin());
    std::vector<std::uint8_t> cut(adj.edge_count(), 0);
    const std::size_t added = geo::add_path(adj, t, far, cut);
    EXPECT_GT(added, 0u);
    EXPECT_EQ(cut_vertex_count(adj, cut), added + 1);
}

TEST(DiskCut, SplittingLeavesNoFaceWithThreeBoundaryCorners) {
    // A strip one triangle wide: every interior edge joins two boundary vertices.
    const geo::Mesh strip = geo::make_grid(5, 1, 5.0, 1.0);
    const geo::MeshAdjacency adj = geo::build_adjacency(strip);
    geo::OpenedMesh o = geo::open_along(strip, adj, geo::initial_cut(strip, adj));
    const std::size_t interior_edges = adj.edge_count() - geo::analyze_topology(strip).boundary_edges;
    EXPECT_EQ(geo::split_dividing_edges(o), interior_edges);
    expect_disk(o.disk, "split strip");
    const geo::MeshAdjacency split = geo::build_adjacency(o.disk);
    std::vector<std::uint8_t> on_boundary(o.disk.vertex_count(), 0);
    for (std::size_t e = 0; e < split.edge_count(); ++e)
        if (split.edge_face_count(e) == 1) on_boundary[split.edges[2 * e]] = on_boundary[split.edges[2 * e + 1]] = 1;
    double area = 0.0, split_area = 0.0;
    for (const glm::uvec3& t : strip.triangles)
        area += 0.5 * glm::length(glm::cross(strip.positions[t.y] - strip.positions[t.x],
                                             strip.positions[t.z] - strip.positions[t.x]));
    for (const glm::uvec3& t : o.disk.triangles) {
        EXPECT_FALSE(on_boundary[t.x] && on_boundary[t.y] && on_boundary[t.z]);
        const glm::dvec3 n =
            glm::cross(o.disk.positions[t.y] - o.disk.positions[t.x], o.disk.positions[t.z] - o.disk.positions[t.x]);
        EXPECT_GT(n.z, 0.0);  // still facing +z: no face turned
        split_area += 0.5 * glm::length(n);
    }
    EXPECT_NEAR(split_area, area, 1e-12);
    EXPECT_EQ(std::count(o.source.begin(), o.source.end(), geo::kInvalidIndex), std::ptrdiff_t(interior_edges));
    // A second pass finds nothing left to split.
    EXPECT_EQ(geo::split_dividing_edges(o), 0u);
}

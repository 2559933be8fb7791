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
#include <map>
#include <numbers>
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

// A unit grid of n x n cells without the cells at the given centres: one hole each.
geo::Mesh holed_grid(int n, const std::vector<glm::dvec2>& holes) {
    geo::Mesh m = geo::make_grid(n, n);
    std::erase_if(m.triangles, [&](const glm::uvec3& t) {
        const glm::dvec3 c = (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0;
        return std::any_of(holes.begin(), holes.end(), [&](const glm::dvec2& h) {
            return std::abs(c.x - h.x) < 0.5 / n && std::abs(c.y - h.y) < 0.5 / n;
        });
    });
    return m;
}

geo::Mesh annulus() { return holed_grid(7, {{0.5, 0.5}}); }

double cut_length(const geo::Mesh& mesh, const geo::MeshAdjacency& adj, const std::vector<std::uint8_t>& cut) {
    double length = 0.0;
    for (std::size_t e = 0; e < cut.size(); ++e)
        if (cut[e]) length += glm::distance(mesh.positions[adj.edges[2 * e]], mesh.positions[adj.edges[2 * e + 1]]);
    return length;
}

// Faces of the mesh opened along the cut with every corner on its boundary.
std::size_t closed_in_faces(const geo::Mesh& mesh, const geo::MeshAdjacency& adj,
                            const std::vector<std::uint8_t>& cut) {
    const geo::OpenedMesh o = geo::open_along(mesh, adj, cut);
    const geo::MeshAdjacency opened = geo::build_adjacency(o.disk);
    std::vector<std::uint8_t> rim(o.disk.vertex_count(), 0);
    for (std::size_t e = 0; e < opened.edge_count(); ++e)
        if (opened.edge_face_count(e) == 1) rim[opened.edges[2 * e]] = rim[opened.edges[2 * e + 1]] = 1;
    return std::size_t(std::count_if(o.disk.triangles.begin(), o.disk.triangles.end(),
                                     [&](const glm::uvec3& t) { return rim[t.x] && rim[t.y] && rim[t.z]; }));
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
    // Its face between the two edges is closed in, but zipping would leave the one edge.
    EXPECT_EQ(geo::zip_closed_in(tetra, adj, cut), 0u);
    EXPECT_EQ(count(cut), 2u);
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

TEST(DiskCut, ATorusesShortestLoopsAreAMeridianAndALongitude) {
    const double R = 2.0, r = 0.6;
    const int ring = 24, tube = 10;
    const geo::Mesh torus = geo::make_torus(R, r, ring, tube);
    const geo::MeshAdjacency adj = geo::build_adjacency(torus);
    const auto loops = geo::initial_cut(torus, adj, geo::CutGraph::ShortestLoops);
    EXPECT_EQ(double(count(loops)) - double(cut_vertex_count(adj, loops)), 1.0);  // genus 1, as above
    const geo::OpenedMesh o = geo::open_along(torus, adj, loops);
    expect_disk(o.disk, "torus, shortest loops");
    expect_same_surface(torus, o);
    // No longer than the tube's polygon and the outer equator's through one vertex, and shorter than
    // the face tree's loops.
    const double meridian = tube * 2.0 * r * std::sin(std::numbers::pi / tube);
    const double equator = ring * 2.0 * (R + r) * std::sin(std::numbers::pi / ring);
    EXPECT_LE(cut_length(torus, adj, loops), meridian + equator + 1e-9);
    EXPECT_LT(cut_length(torus, adj, loops), cut_length(torus, adj, geo::initial_cut(torus, adj)));
}

TEST(DiskCut, FreeRimsEnterEveryHoleOnce) {
    const geo::Mesh grid = holed_grid(9, {{0.3, 0.5}, {0.7, 0.5}});
    const geo::MeshAdjacency adj = geo::build_adjacency(grid);
    std::vector<std::uint8_t> rim(grid.vertex_count(), 0), sources(grid.vertex_count(), 0);
    for (std::size_t e = 0; e < adj.edge_count(); ++e)
        if (adj.edge_face_count(e) == 1) rim[adj.edges[2 * e]] = rim[adj.edges[2 * e + 1]] = 1;
    sources[0] = 1;  // a corner, on the outer rim
    const geo::PathTree t = geo::shortest_paths(grid, adj, sources, true);
    // Each of the three rims: every vertex at one distance (the outer rim's 0, the holes' the two
    // cells to the nearest border), and one vertex reached from off the rim.
    auto which = [&](const glm::dvec3& p) {
        return p.x == 0.0 || p.y == 0.0 || p.x == 1.0 || p.y == 1.0 ? 0 : p.x < 0.5 ? 1 : 2;
    };
    std::map<int, std::set<double>> distances;
    std::map<int, int> vertices, entries;
    for (std::uint32_t v = 0; v < grid.vertex_count(); ++v)
        if (rim[v]) {
            const int k = which(grid.positions[v]);
            distances[k].insert(t.distance[v]);
            ++vertices[k];
            entries[k] +=
                t.previous[v] == geo::kInvalidIndex || adj.edge_face_count(adj.find_edge(v, t.previous[v])) != 1;
        }
    EXPECT_EQ(vertices[0], 4 * 9);
    EXPECT_EQ(vertices[1], 4);  // a hole of one cell
    EXPECT_EQ(vertices[2], 4);
    for (int k : {0, 1, 2}) {
        ASSERT_EQ(distances[k].size(), 1u) << k;
        EXPECT_NEAR(*distances[k].begin(), k == 0 ? 0.0 : 2.0 / 9.0, 1e-12) << k;
        EXPECT_EQ(entries[k], 1) << k;
    }
    // Without free rims a rim's vertices are reached at different distances.
    const geo::PathTree plain = geo::shortest_paths(grid, adj, sources);
    EXPECT_GT(plain.distance[9], 0.0);  // the outer rim's next corner
}

TEST(DiskCut, TheShortestLoopsCutJoinsTheHolesByShortestPaths) {
    const geo::Mesh grid = holed_grid(9, {{0.3, 0.5}, {0.7, 0.5}});
    const geo::MeshAdjacency adj = geo::build_adjacency(grid);
    const auto cut = geo::initial_cut(grid, adj, geo::CutGraph::ShortestLoops);
    // Two paths joining three rims: a forest of two trees, each edge a path's.
    EXPECT_EQ(cut_vertex_count(adj, cut), count(cut) + 2);
    expect_disk(geo::open_along(grid, adj, cut).disk, "two holes, shortest loops");
    // The holes are 3 cells from the border and 3 from each other (cells 0.111 wide): no more than
    // the two straight paths from the border to one hole and between the holes.
    EXPECT_LE(cut_length(grid, adj, cut), 2 * 3 / 9.0 + 1e-12);
}

TEST(DiskCut, ZippingGluesAStripBetweenTwoPathsToOneOfThem) {
    // Two slits from the left border along rows 5 and 6 to column 6: the cells between them have
    // every corner on the cut and meet the rest of the grid at the edge (6, 5)-(6, 6).
    const int n = 10;
    const geo::Mesh grid = geo::make_grid(n, n);
    const geo::MeshAdjacency adj = geo::build_adjacency(grid);
    auto id = [&](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
    std::vector<std::uint8_t> cut(adj.edge_count(), 0);
    for (int j : {5, 6})
        for (int i = 0; i < 6; ++i) cut[adj.find_edge(id(i, j), id(i + 1, j))] = 1;
    expect_disk(geo::open_along(grid, adj, cut).disk, "two slits");
    // The 12 between the slits, one at their root on the border and two of the grid's corners.
    EXPECT_EQ(closed_in_faces(grid, adj, cut), 15u);
    EXPECT_EQ(geo::zip_closed_in(grid, adj, cut), 1u);
    // One slit stays, bent up (or down) to the other's end: 7 edges, 0.7 long.
    EXPECT_EQ(count(cut), 7u);
    EXPECT_NEAR(cut_length(grid, adj, cut), 0.7, 1e-12);
    EXPECT_EQ(cut[adj.find_edge(id(6, 5), id(6, 6))], 1);
    EXPECT_EQ(closed_in_faces(grid, adj, cut), 3u);  // single faces at one edge: nothing to gain
    expect_disk(geo::open_along(grid, adj, cut).disk, "zipped");
    EXPECT_EQ(geo::zip_closed_in(grid, adj, cut), 0u);  // nothing left to zip
}

TEST(DiskCut, ZippingLeavesACutWithoutStripsAlone) {
    const geo::Mesh torus = geo::make_torus(2.0, 0.6, 24, 10);
    const geo::MeshAdjacency adj = geo::build_adjacency(torus);
    auto cut = geo::initial_cut(torus, adj, geo::CutGraph::ShortestLoops);
    // Two single faces where the loops cross, each between two of their edges: moving the cut
    // across one would not shorten it.
    ASSERT_EQ(closed_in_faces(torus, adj, cut), 2u);
    const auto before = cut;
    EXPECT_EQ(geo::zip_closed_in(torus, adj, cut), 0u);
    EXPECT_EQ(cut, before);
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

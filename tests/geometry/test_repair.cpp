// repair_mesh on meshes whose defects and repairs are known by construction, and on the messy
// shared meshes (skipped where ../shared/meshes is absent).
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/repair.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/topology.h"
#include "gimg/geometry/weld.h"

#include "test_data.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>

namespace geo = gimg::geo;

namespace {

constexpr double kPi = 3.14159265358979323846;

double area(const geo::Mesh& m) {
    double sum = 0.0;
    for (const glm::uvec3& t : m.triangles)
        sum += 0.5 * glm::length(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
    return sum;
}

void append(geo::Mesh& to, const geo::Mesh& from, glm::dvec3 offset = glm::dvec3(0.0)) {
    const auto base = std::uint32_t(to.positions.size());
    for (const glm::dvec3& p : from.positions) to.positions.push_back(p + offset);
    for (const glm::uvec3& t : from.triangles) to.triangles.push_back(t + base);
}

void expect_clean(const geo::Mesh& m) {
    const geo::MeshInfo info = geo::analyze_topology(m);
    EXPECT_TRUE(info.manifold) << info.non_manifold_edges << " edges, " << info.non_manifold_vertices << " vertices";
    EXPECT_TRUE(info.oriented) << info.inconsistent_edges << " inconsistent edges";
    EXPECT_EQ(info.degenerate_faces, 0u);
    EXPECT_EQ(info.duplicate_faces, 0u);
    EXPECT_EQ(info.isolated_vertices, 0u);
}

// A strip of `columns` quads around a circle, one quad high, glued end to end with a half twist.
geo::Mesh moebius(int columns) {
    geo::Mesh m;
    for (int i = 0; i < columns; ++i) {
        const double u = 2 * kPi * i / columns;
        for (int side : {-1, 1}) {
            const double w = 0.3 * side;
            m.positions.emplace_back((2 + w * std::cos(u / 2)) * std::cos(u), (2 + w * std::cos(u / 2)) * std::sin(u),
                                     w * std::sin(u / 2));
        }
    }
    for (int i = 0; i < columns; ++i) {
        const unsigned a = 2 * i, b = 2 * i + 1;
        // The last column's far side is the first column with its two vertices swapped.
        const unsigned c = i + 1 < columns ? 2 * i + 2 : 1, d = i + 1 < columns ? 2 * i + 3 : 0;
        m.triangles.push_back({a, c, d});
        m.triangles.push_back({a, d, b});
    }
    return m;
}

}  // namespace

TEST(Repair, LeavesAManifoldOrientedMeshAsItIs) {
    for (const geo::Mesh& original : {geo::make_torus(2.0, 0.5, 24, 12), geo::make_icosphere(1.0, 2)}) {
        geo::Mesh m = original;
        const geo::RepairReport r = geo::repair_mesh(m);
        EXPECT_FALSE(r.changed());
        EXPECT_EQ(m.positions, original.positions);
        EXPECT_EQ(m.triangles, original.triangles);
    }
}

TEST(Repair, TurnsBackTheFacesThatDisagreeWithMostOfTheirPiece) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 2);
    geo::Mesh m = sphere;
    for (std::size_t f : {0, 7, 33, 100, 250}) std::swap(m.triangles[f].y, m.triangles[f].z);
    EXPECT_FALSE(geo::analyze_topology(m).oriented);
    EXPECT_EQ(geo::repair_mesh(m).turned_faces, 5u);
    EXPECT_EQ(m.triangles, sphere.triangles);

    // Inside out but for three faces: the piece keeps the orientation of most of its area.
    geo::Mesh inside_out = sphere;
    for (std::size_t f = 3; f < inside_out.triangles.size(); ++f)
        std::swap(inside_out.triangles[f].y, inside_out.triangles[f].z);
    EXPECT_EQ(geo::repair_mesh(inside_out).turned_faces, 3u);
    for (std::size_t f = 0; f < sphere.triangles.size(); ++f)
        EXPECT_EQ(inside_out.triangles[f],
                  glm::uvec3(sphere.triangles[f].x, sphere.triangles[f].z, sphere.triangles[f].y));
}

TEST(Repair, OpensAMoebiusStripIntoAnOrientedBand) {
    geo::Mesh m = moebius(16);
    ASSERT_FALSE(geo::analyze_topology(m).orientable);
    const geo::RepairReport r = geo::repair_mesh(m);
    EXPECT_EQ(r.opened_edges, 1u);
    expect_clean(m);
    const geo::MeshInfo info = geo::analyze_topology(m);
    EXPECT_EQ(info.components, 1u);
    EXPECT_EQ(info.boundary_loops, 1u);  // a disk: the band cut across once
    EXPECT_EQ(info.component_info[0].euler_characteristic, 1);
    EXPECT_EQ(m.triangles.size(), 32u);
}

TEST(Repair, TwoCubesTouchingAlongAnEdgeStayTwoClosedCubes) {
    geo::Mesh m = geo::make_box({1, 1, 1});
    append(m, geo::make_box({1, 1, 1}), {1, 1, 0});
    ASSERT_EQ(geo::weld_identical_vertices(m), 2u);
    ASSERT_EQ(geo::analyze_topology(m).non_manifold_edges, 1u);
    const double before = area(m);
    const geo::RepairReport r = geo::repair_mesh(m);
    EXPECT_EQ(r.opened_edges, 0u);  // the four faces on the edge paired, each with its own cube's
    EXPECT_EQ(r.split_vertices, 2u);
    EXPECT_EQ(r.dropped_faces, 0u);
    expect_clean(m);
    const geo::MeshInfo info = geo::analyze_topology(m);
    ASSERT_EQ(info.components, 2u);
    EXPECT_TRUE(info.closed);
    for (const geo::ComponentInfo& c : info.component_info) EXPECT_EQ(c.genus, 0);
    EXPECT_DOUBLE_EQ(area(m), before);
}

TEST(Repair, DetachesAFinStandingOnTheFrontOfASurface) {
    geo::Mesh m = geo::make_grid(4, 4);  // 4 x 4 vertices, facing +z
    const glm::dvec3 normal = glm::cross(m.positions[m.triangles[0].y] - m.positions[m.triangles[0].x],
                                         m.positions[m.triangles[0].z] - m.positions[m.triangles[0].x]);
    ASSERT_GT(normal.z, 0.0);
    // An interior edge of the grid (a face's first side that another face has too), and a
    // triangle standing on it in front, either way round.
    const geo::MeshInfo grid = geo::analyze_topology(m);
    auto has_side = [&](const glm::uvec3& t, std::uint32_t a, std::uint32_t b) {
        return (t.x == a || t.y == a || t.z == a) && (t.x == b || t.y == b || t.z == b);
    };
    int interior = -1;
    for (std::size_t f = 0; f < m.triangles.size() && interior < 0; ++f)
        for (std::size_t g = 0; g < m.triangles.size(); ++g)
            if (g != f && has_side(m.triangles[g], m.triangles[f].x, m.triangles[f].y)) interior = int(f);
    ASSERT_GE(interior, 0);
    for (bool reversed : {false, true}) {
        geo::Mesh fin = m;
        const glm::uvec3 t = fin.triangles[std::size_t(interior)];
        const glm::dvec3 mid = 0.5 * (fin.positions[t.x] + fin.positions[t.y]);
        fin.positions.push_back(mid + glm::dvec3(0, 0, 0.5));
        fin.texcoords.push_back({0.5, 0.5});
        const auto top = std::uint32_t(fin.positions.size() - 1);
        fin.triangles.push_back(reversed ? glm::uvec3(t.y, t.x, top) : glm::uvec3(t.x, t.y, top));
        ASSERT_GE(geo::analyze_topology(fin).non_manifold_edges, 1u);
        const geo::RepairReport r = geo::repair_mesh(fin);
        EXPECT_EQ(r.opened_edges, 1u);
        expect_clean(fin);
        const geo::MeshInfo info = geo::analyze_topology(fin);
        ASSERT_EQ(info.components, 2u) << "reversed " << reversed;
        EXPECT_EQ(info.component_info[0].faces, m.triangles.size());
        EXPECT_EQ(info.component_info[0].boundary_loops, grid.boundary_loops) << "the grid stays whole";
    }
}

TEST(Repair, SplitsABowtieAndCopiesTheTextureCoordinate) {
    geo::Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    m.texcoords = {{0.5, 0.5}, {1, 0.5}, {1, 1}, {0, 0.5}, {0, 0}};
    m.triangles = {{0, 1, 2}, {0, 3, 4}};
    const geo::RepairReport r = geo::repair_mesh(m);
    EXPECT_EQ(r.split_vertices, 1u);
    expect_clean(m);
    ASSERT_EQ(m.positions.size(), 6u);
    EXPECT_EQ(m.positions[5], m.positions[0]);
    EXPECT_EQ(m.texcoords[5], m.texcoords[0]);
    EXPECT_EQ(geo::analyze_topology(m).components, 2u);
}

TEST(Repair, FlipsACapOfZeroAreaAway) {
    // The unit square a b c d, and m on its diagonal a c: the face a c m has no area.
    geo::Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 4}, {4, 2, 3}, {0, 4, 3}};
    ASSERT_EQ(geo::analyze_topology(m).zero_area_faces, 1u);
    const geo::RepairReport r = geo::repair_mesh(m);
    EXPECT_EQ(r.zero_area_faces, 1u);
    EXPECT_EQ(r.flipped_edges, 1u);
    EXPECT_EQ(r.zero_area_left, 0u);
    expect_clean(m);
    EXPECT_EQ(m.triangles.size(), 4u);  // the fan of four around m
    EXPECT_DOUBLE_EQ(area(m), 1.0);
    for (const glm::uvec3& t : m.triangles) {
        EXPECT_TRUE(t.x == 4 || t.y == 4 || t.z == 4);
        const glm::dvec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
        EXPECT_DOUBLE_EQ(n.z, 0.5);  // a quarter of the square, facing +z
    }
}

TEST(Repair, CollapsesANeedleAndDropsACapOnTheBoundary) {
    // The unit square with its corner c doubled as e at the same place: a c e and e c d have no area.
    geo::Mesh needle;
    needle.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 1, 0}};
    needle.triangles = {{0, 1, 2}, {0, 2, 4}, {0, 4, 3}, {4, 2, 3}};
    geo::RepairReport r = geo::repair_mesh(needle);
    EXPECT_EQ(r.zero_area_faces, 2u);
    EXPECT_EQ(r.collapsed_edges, 1u);
    EXPECT_EQ(r.zero_area_left, 0u);
    expect_clean(needle);
    EXPECT_EQ(needle.triangles.size(), 2u);
    EXPECT_EQ(needle.positions.size(), 4u);
    EXPECT_DOUBLE_EQ(area(needle), 1.0);

    // A cap whose longest edge is on the boundary: the square with m on its side a b, and a b m.
    geo::Mesh cap;
    cap.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0, 0}};
    cap.triangles = {{0, 4, 1}, {4, 2, 1}, {0, 2, 4}, {0, 3, 2}};
    ASSERT_EQ(geo::analyze_topology(cap).zero_area_faces, 1u);
    r = geo::repair_mesh(cap);
    EXPECT_EQ(r.zero_area_left, 0u);
    expect_clean(cap);
    EXPECT_EQ(cap.triangles.size(), 3u);
    EXPECT_DOUBLE_EQ(area(cap), 1.0);
}

TEST(Repair, RemovesCollapsedAndDuplicateFacesAndKeepsTheLargestPiece) {
    geo::Mesh m = geo::make_icosphere(1.0, 1);
    const std::size_t sphere_faces = m.triangles.size();
    const glm::uvec3 first = m.triangles[0];
    m.triangles.push_back({first.x, first.z, first.y});  // the first face again, turned
    m.triangles.push_back({first.x, first.x, first.y});
    append(m, geo::make_icosphere(0.5, 0), {3, 0, 0});
    m.positions.push_back({9, 9, 9});  // in no face
    geo::Mesh all = m;
    geo::RepairReport r = geo::repair_mesh(all);
    EXPECT_EQ(r.duplicate_faces, 1u);
    EXPECT_EQ(r.collapsed_faces, 1u);
    EXPECT_EQ(r.unused_vertices, 1u);
    expect_clean(all);
    EXPECT_EQ(geo::analyze_topology(all).components, 2u);

    r = geo::repair_mesh(m, {.largest = true});
    EXPECT_EQ(r.dropped_pieces, 1u);
    EXPECT_EQ(r.unused_vertices, 13u);  // the small sphere's 12 and the lone one
    expect_clean(m);
    EXPECT_EQ(m.triangles.size(), sphere_faces);
}

TEST(Repair, RefusesWhatItCannotRead) {
    geo::Mesh bad = geo::make_icosphere(1.0, 0);
    bad.triangles.push_back({0, 1, 99});
    EXPECT_THROW(geo::repair_mesh(bad), geo::InputError);
    geo::Mesh nan = geo::make_icosphere(1.0, 0);
    nan.positions[3].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(geo::repair_mesh(nan), geo::InputError);
    geo::Mesh none;
    none.positions = {{0, 0, 0}};
    none.triangles = {{0, 0, 0}};
    geo::repair_mesh(none);
    EXPECT_TRUE(none.triangles.empty());
    EXPECT_TRUE(none.positions.empty());
}

// The shared meshes of messy real data come out manifold, oriented and without degenerate or
// duplicate faces, their surface kept but for the few faces dropped.
TEST(Repair, MessySharedMeshesComeOutClean) {
    for (const char* name : {"teapot.obj", "snowden_lo.obj", "dragon_res4.ply"}) {
        GIMG_REQUIRE_SHARED_MESH(path, name);
        geo::Mesh m = geo::load_mesh(path);
        geo::Mesh unique = m;
        geo::RepairReport r = geo::repair_mesh(unique, {.weld = true});
        expect_clean(unique);
        const geo::MeshInfo before = geo::analyze_topology(m);
        EXPECT_EQ(r.duplicate_faces, before.duplicate_faces) << name;
        // The area of the input's distinct faces, less what was dropped (at most 0.5 % of them).
        EXPECT_LE(r.dropped_faces, before.faces / 200) << name;
        double distinct = 0.0;
        std::set<std::array<std::uint32_t, 3>> seen;
        geo::weld_identical_vertices(m);
        for (const glm::uvec3& t : m.triangles) {
            std::array<std::uint32_t, 3> key{t.x, t.y, t.z};
            std::sort(key.begin(), key.end());
            if (seen.insert(key).second)
                distinct += 0.5 * glm::length(glm::cross(m.positions[t.y] - m.positions[t.x],
                                                         m.positions[t.z] - m.positions[t.x]));
        }
        EXPECT_NEAR(area(unique), distinct, 0.005 * distinct) << name;
    }
}

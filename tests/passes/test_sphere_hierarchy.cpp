// The progressive-mesh hierarchy under the spherical parameterizations: every level a closed,
// manifold, oriented genus-0 mesh without degenerate faces, the last level the input itself, and
// the vertex-split replay agreeing with the levels.
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/topology.h"
#include "gimg/geometry/progressive_mesh.h"
#include "gimg/geometry/progressive_replay.h"
#include "sphere/hierarchy/sphere_hierarchy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using namespace gimg;
using geo::HierarchyLevel;

namespace {

// A closed, manifold, consistently oriented genus-0 surface on exactly the vertices it names.
void expect_sphere_topology(const geo::Mesh& full, const std::vector<glm::uvec3>& triangles, std::size_t vertices,
                            bool check_geometry, const std::string& what) {
    geo::Mesh m;
    m.positions = full.positions;
    m.triangles = triangles;
    const geo::MeshInfo info = geo::analyze_topology(m);
    EXPECT_EQ(info.components, 1u) << what;
    EXPECT_EQ(info.vertices - info.isolated_vertices, vertices) << what;
    EXPECT_TRUE(info.closed) << what;
    EXPECT_TRUE(info.manifold) << what;
    EXPECT_TRUE(info.oriented) << what;
    EXPECT_EQ(info.non_manifold_vertices, 0u) << what;
    EXPECT_EQ(info.duplicate_faces, 0u) << what;
    EXPECT_EQ(info.collapsed_faces, 0u) << what;
    if (check_geometry) {
        EXPECT_EQ(info.degenerate_faces, 0u) << what;
    }
    ASSERT_FALSE(info.component_info.empty()) << what;
    EXPECT_EQ(info.component_info.front().genus.value_or(-1), 0) << what;
}

void expect_valid_hierarchy(const geo::Mesh& mesh, std::size_t base, double growth) {
    const std::vector<geo::HierarchyLevel> levels = passes::detail::build_sphere_hierarchy(mesh, base, growth);
    ASSERT_FALSE(levels.empty());
    EXPECT_LE(levels.front().vertices.size(), std::max<std::size_t>(base, 4));
    EXPECT_TRUE(levels.front().added.empty());
    std::set<std::uint32_t> seen;
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const geo::HierarchyLevel& level = levels[i];
        const std::string what =
            "level " + std::to_string(i) + " (" + std::to_string(level.vertices.size()) + " vertices)";
        expect_sphere_topology(mesh, level.triangles, level.vertices.size(), true, what);
        // Euler: a closed genus-0 triangle mesh has 2V - 4 faces.
        EXPECT_EQ(level.triangles.size(), 2 * level.vertices.size() - 4) << what;
        std::set<std::uint32_t> named;
        for (const glm::uvec3& t : level.triangles) named.insert({t.x, t.y, t.z});
        EXPECT_EQ(named, std::set<std::uint32_t>(level.vertices.begin(), level.vertices.end())) << what;
        ASSERT_EQ(level.added.size(), level.parent.size()) << what;
        if (i == 0) {
            seen.insert(level.vertices.begin(), level.vertices.end());
            continue;
        }
        const std::size_t before = levels[i - 1].vertices.size();
        EXPECT_EQ(level.vertices.size(), before + level.added.size()) << what;
        EXPECT_TRUE(std::equal(levels[i - 1].vertices.begin(), levels[i - 1].vertices.end(), level.vertices.begin()));
        if (i + 1 < levels.size()) {
            EXPECT_EQ(level.vertices.size(), std::size_t(std::round(double(before) * growth))) << what;
        }
        for (std::size_t j = 0; j < level.added.size(); ++j) {
            EXPECT_TRUE(seen.count(level.parent[j])) << what << ": parent of " << level.added[j] << " not active yet";
            EXPECT_TRUE(seen.insert(level.added[j]).second) << what << ": " << level.added[j] << " added twice";
        }
    }
    EXPECT_EQ(levels.back().vertices.size(), mesh.vertex_count());
    EXPECT_EQ(levels.back().triangles, mesh.triangles);  // same faces, same order, same corner order
}

}  // namespace

TEST(SphereHierarchy, IcosphereLevelsAreClosedGenusZeroAndEndAtTheInput) {
    expect_valid_hierarchy(geo::make_icosphere(1.0, 3), 40, 2.0);
}

TEST(SphereHierarchy, UvSphereWithThinPolarTrianglesAndAnOddGrowth) {
    expect_valid_hierarchy(geo::make_uv_sphere(32, 16), 30, 1.7);
}

TEST(SphereHierarchy, SharedMeshesKeepSphereTopologyAtEveryLevel) {
    for (const char* name : {"hand.off", "bunny_small.obj", "blobby.off"}) {
        auto path = test::shared_mesh(name);
        if (!path) GTEST_SKIP() << "shared mesh " << name << " not found (set GIMG_MESH_DIR)";
        SCOPED_TRACE(name);
        expect_valid_hierarchy(geo::load_mesh(*path), 300, 2.0);
    }
}

TEST(SphereHierarchy, CollapsesReachATetrahedronAndTheReplayMatchesTheLevels) {
    const geo::Mesh mesh = geo::make_icosphere(1.0, 2);
    const geo::ProgressiveMesh pm = geo::build_progressive_mesh(mesh, 60);
    EXPECT_EQ(pm.coarsest_count(), 4u);
    EXPECT_EQ(pm.base_vertex_count, 60u);
    EXPECT_EQ(pm.coarsest_count() + pm.splits.size(), mesh.vertex_count());
    geo::ProgressiveReplay replay(pm, pm.coarsest_count());
    while (true) {
        const std::size_t n = replay.active_count();
        const std::vector<glm::uvec3> live = replay.live_triangles();
        ASSERT_EQ(live, geo::triangles_at(pm, n)) << n << " vertices";
        // Below the base only the link condition holds the collapses back: topology, not geometry.
        expect_sphere_topology(mesh, live, n, n >= pm.base_vertex_count, std::to_string(n) + " vertices");
        for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
            for (std::uint32_t f : replay.faces_of(v)) {
                const glm::uvec3 t = replay.triangles()[f];
                ASSERT_TRUE(t.x == v || t.y == v || t.z == v);
            }
        if (replay.complete()) break;
        const geo::VertexSplit& s = replay.split_next();
        const glm::uvec3 a = replay.triangles()[s.born_faces[0]], b = replay.triangles()[s.born_faces[1]];
        EXPECT_TRUE((a.x == s.left || a.y == s.left || a.z == s.left) &&
                    (b.x == s.right || b.y == s.right || b.z == s.right));
    }
    EXPECT_EQ(replay.live_triangles(), mesh.triangles);
}

TEST(SphereHierarchy, BadGrowthAndTinyMeshes) {
    const geo::Mesh mesh = geo::make_icosphere(1.0, 1);
    EXPECT_THROW(passes::detail::build_sphere_hierarchy(mesh, 10, 1.0), geo::InputError);
    // A mesh smaller than the base is its own base: one level.
    const auto levels = passes::detail::build_sphere_hierarchy(mesh, 1000, 2.0);
    ASSERT_EQ(levels.size(), 1u);
    EXPECT_EQ(levels.front().triangles, mesh.triangles);
}

// The direct route's input check from its laid-out level (sphere/harmonic/relaxation_mesh_check.h) accepts exactly
// what check_sphere_input accepts: on every shared mesh and on each defect the full check names.
#include "test_data.h"

#include "sphere/harmonic/relaxation_mesh_check.h"
#include "sphere/harmonic/relaxation_mesh.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/sphere.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

using namespace gimg;

namespace {

bool full_check_accepts(const geo::Mesh& mesh) {
    try {
        passes::check_sphere_input(mesh);
        return true;
    } catch (const geo::InputError&) {
        return false;
    }
}

bool level_check_accepts(const geo::Mesh& mesh) {
    try {
        const passes::detail::RelaxationMesh level = passes::detail::build_relaxation_mesh(mesh);
        return passes::detail::relaxation_mesh_is_sphere(mesh, level);
    } catch (const geo::InputError&) {
        return false;
    }
}

// Both checks' answer, which must agree.
bool accepted(const geo::Mesh& mesh, const std::string& what) {
    const bool full = full_check_accepts(mesh);
    EXPECT_EQ(level_check_accepts(mesh), full) << what;
    return full;
}

geo::Mesh tetrahedron() {
    geo::Mesh m;
    m.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    m.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    return m;
}

// `b` appended to `a`, its vertices renumbered after a's.
geo::Mesh joined(geo::Mesh a, const geo::Mesh& b) {
    const auto offset = std::uint32_t(a.positions.size());
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (glm::uvec3 t : b.triangles) a.triangles.push_back(t + offset);
    return a;
}

}  // namespace

TEST(SphereLevelTopology, AcceptsClosedGenusZeroSurfaces) {
    EXPECT_TRUE(accepted(tetrahedron(), "tetrahedron"));
    EXPECT_TRUE(accepted(geo::make_icosphere(1.0, 3), "icosphere"));
    EXPECT_TRUE(accepted(geo::make_box(glm::dvec3(1.0, 2.0, 3.0), 3), "box"));
}

TEST(SphereLevelTopology, RefusesWhatTheFullCheckRefuses) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 2);
    EXPECT_FALSE(accepted(geo::make_torus(2.0, 0.5, 16, 8), "torus (genus 1)"));
    EXPECT_FALSE(accepted(geo::make_grid(4, 4), "grid (open)"));
    EXPECT_FALSE(accepted(joined(sphere, geo::make_icosphere(1.0, 1, glm::dvec3(3.0, 0.0, 0.0))), "two spheres"));
    {
        geo::Mesh m = sphere;
        m.triangles.pop_back();
        EXPECT_FALSE(accepted(m, "a hole"));
    }
    {
        geo::Mesh m = sphere;
        m.triangles.push_back(m.triangles.front());
        EXPECT_FALSE(accepted(m, "a duplicate face"));
    }
    {
        geo::Mesh m = sphere;
        const glm::uvec3 t = m.triangles.front();
        m.triangles.push_back({t.x, t.z, t.y});
        EXPECT_FALSE(accepted(m, "a duplicate face, turned over"));
    }
    {
        geo::Mesh m = sphere;
        std::swap(m.triangles[5].y, m.triangles[5].z);
        EXPECT_FALSE(accepted(m, "a face turned over"));
    }
    {
        geo::Mesh m = sphere;
        m.triangles.push_back({0, 0, 1});
        EXPECT_FALSE(accepted(m, "a collapsed face"));
    }
    {
        // Vertex 0 moved onto the line through two neighbours of one of its triangles.
        geo::Mesh m = sphere;
        const glm::uvec3 t = m.triangles.front();
        const std::uint32_t v = t.x, a = t.y, b = t.z;
        m.positions[v] = 2.0 * m.positions[a] - m.positions[b];
        EXPECT_FALSE(accepted(m, "a zero-area face"));
    }
    {
        geo::Mesh m = sphere;
        m.positions.push_back(glm::dvec3(5.0));
        EXPECT_FALSE(accepted(m, "an isolated vertex"));
    }
    {
        geo::Mesh m;
        m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        m.triangles = {{0, 1, 2}, {0, 2, 1}};
        EXPECT_FALSE(accepted(m, "one triangle twice (a pillow)"));
    }
    {
        // Two tetrahedra sharing an edge (non-manifold edge) or a vertex (non-manifold vertex).
        geo::Mesh edge = tetrahedron(), vertex = tetrahedron();
        geo::Mesh other = tetrahedron();
        for (auto& p : other.positions) p += glm::dvec3(3.0, 0.0, 0.0);
        edge = joined(edge, other);
        vertex = joined(vertex, other);
        for (auto& t : edge.triangles)
            for (int k = 0; k < 3; ++k) {
                if (t[k] == 4)
                    t[k] = 0;
                else if (t[k] == 5)
                    t[k] = 1;
            }
        for (auto& t : vertex.triangles)
            for (int k = 0; k < 3; ++k)
                if (t[k] == 4) t[k] = 0;
        EXPECT_FALSE(accepted(edge, "two tetrahedra on one edge"));
        EXPECT_FALSE(accepted(vertex, "two tetrahedra on one vertex"));
    }
    {
        geo::Mesh m;
        EXPECT_FALSE(accepted(m, "no faces"));
    }
}

TEST(SphereLevelTopology, AgreesWithTheFullCheckOnEverySharedMesh) {
    const auto dir = test::mesh_dir();
    if (!dir) GTEST_SKIP() << "../shared/meshes not found (set GIMG_MESH_DIR)";
    std::size_t meshes = 0, accepted_meshes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(*dir)) {
        const std::string ext = entry.path().extension().string();
        if (ext != ".off" && ext != ".obj" && ext != ".ply") continue;
        geo::Mesh mesh;
        try {
            mesh = geo::load_mesh(entry.path());
        } catch (const geo::InputError&) {
            continue;  // not a mesh the loaders take; the loaders' tests say which
        }
        ++meshes;
        accepted_meshes += accepted(mesh, entry.path().filename().string());
    }
    std::printf("%zu shared meshes, %zu closed genus-0\n", meshes, accepted_meshes);
    EXPECT_GE(meshes, 30u);
    EXPECT_GE(accepted_meshes, 11u);  // the gpu method's test meshes
}

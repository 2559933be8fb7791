// The spherical-map metrics and input checks, on cases with known answers.
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/sphere.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <numbers>

using namespace gimg;

namespace {
std::vector<glm::dvec3> normalized(const geo::Mesh& m) {
    std::vector<glm::dvec3> y;
    for (const auto& p : m.positions) y.push_back(glm::normalize(p));
    return y;
}

std::string message_of(const geo::Mesh& m) {
    try {
        passes::check_sphere_input(m);
    } catch (const geo::InputError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(SphereMetrics, ASphereMappedToItselfIsPerfect) {
    const geo::Mesh s = geo::make_icosphere(1.0, 4);
    const passes::SphereMetrics m = passes::sphere_metrics(s, normalized(s));
    EXPECT_EQ(m.flips, 0u);
    // F = sum over faces of twice their area: the inscribed polyhedron's area, just under 4 pi.
    EXPECT_LT(m.conformal_ratio, 1.0);
    EXPECT_GT(m.conformal_ratio, 0.99);
    EXPECT_LT(m.angle_distortion_deg.max, 1e-9);
    EXPECT_LT(m.area_distortion, 1e-9);
}

TEST(SphereMetrics, AMirroredMapFlipsEveryTriangleAndStretchingShowsUp) {
    const geo::Mesh s = geo::make_icosphere(1.0, 3);
    std::vector<glm::dvec3> mirrored = normalized(s);
    for (auto& p : mirrored) p.x = -p.x;
    EXPECT_EQ(passes::sphere_metrics(s, mirrored).flips, s.face_count());

    geo::Mesh ellipsoid = s;
    for (auto& p : ellipsoid.positions) p.y *= 2.0;
    const passes::SphereMetrics m = passes::sphere_metrics(ellipsoid, normalized(s));
    EXPECT_EQ(m.flips, 0u);
    EXPECT_GT(m.angle_distortion_deg.mean, 1.0);  // the identity onto the sphere is not conformal here
    EXPECT_GT(m.area_distortion, 0.05);
}

TEST(SphereInput, WrongTopologyIsNamed) {
    EXPECT_EQ(message_of(geo::make_icosphere(1.0, 2)), "");
    EXPECT_NE(message_of(geo::make_torus(2.0, 0.5, 12, 8)).find("genus 1: spherical parameterization needs genus 0"),
              std::string::npos);
    EXPECT_NE(message_of(geo::make_grid(3, 3)).find("1 boundary loop"), std::string::npos);
    geo::Mesh two = geo::make_icosphere(1.0, 1);
    const geo::Mesh other = geo::make_icosphere(1.0, 1, {5, 0, 0});
    const auto offset = std::uint32_t(two.positions.size());
    two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
    for (auto t : other.triangles) two.triangles.push_back(t + glm::uvec3(offset));
    EXPECT_NE(message_of(two).find("2 separate pieces"), std::string::npos);
    geo::Mesh fin = geo::make_icosphere(1.0, 1);  // a third face on an edge
    const glm::uvec3 t0 = fin.triangles[0];
    fin.positions.push_back({3, 3, 3});
    fin.triangles.push_back({t0.x, t0.y, std::uint32_t(fin.positions.size() - 1)});
    EXPECT_NE(message_of(fin).find("non-manifold edge at"), std::string::npos);
    EXPECT_NE(message_of(geo::Mesh{}).find("no faces"), std::string::npos);
}

TEST(SphereInput, EverySharedMeshWithHolesOrHandlesIsRefused) {
    for (const char* name :
         {"eight.off", "elk.off", "couplingdown.off", "elephant.off", "knot1.off", "anchor_dense.off", "femur.off",
          "cheese.off", "turbine.off", "nefertiti.off", "terrain.obj", "pig.off", "holes.off",
          "elephant_with_holes.off", "snowden.obj", "dragon_res3.ply", "teapot.obj"}) {
        auto path = gimg::test::shared_mesh(name);
        if (!path) GTEST_SKIP() << "shared meshes not found (set GIMG_MESH_DIR)";
        const std::string why = message_of(geo::load_mesh(*path));
        EXPECT_FALSE(why.empty()) << name;
        std::printf("%-24s %s\n", name, why.c_str());
    }
}

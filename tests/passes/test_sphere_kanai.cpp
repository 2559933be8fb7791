// Kanai's hierarchical conformal spherical parameterization: the identity on a sphere, small
// distortion on an ellipsoid, no flips and an energy near 8 pi on real meshes, never worse than
// Gu's where Gu gets there. Fast cases only; all shared meshes are in long_sphere_meshes.cpp.
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/sphere.h"

#include <gtest/gtest.h>

#include <numbers>

using namespace gimg;

namespace {

geo::Mesh ellipsoid(int level) {
    geo::Mesh m = geo::make_icosphere(1.0, level);
    for (auto& p : m.positions) p.y *= 2.0;
    return m;
}

}  // namespace

TEST(SphereKanai, ASphereMapsToItself) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 4);
    const passes::SphereResult r = passes::sphere_kanai(sphere);
    EXPECT_TRUE(r.converged) << r.note;
    const passes::SphereMetrics m = passes::sphere_metrics(sphere, r.positions);
    EXPECT_EQ(m.flips, 0u);
    EXPECT_LT(m.angle_distortion_deg.max, 0.5);
    EXPECT_LT(m.area_distortion, 0.02);
}

TEST(SphereKanai, AnEllipsoidWithSmallDistortion) {
    const geo::Mesh e = ellipsoid(4);
    const passes::SphereResult r = passes::sphere_kanai(e);
    EXPECT_TRUE(r.converged) << r.note;
    const passes::SphereMetrics m = passes::sphere_metrics(e, r.positions);
    EXPECT_EQ(m.flips, 0u);
    EXPECT_LT(m.angle_distortion_deg.mean, 1.0);
    EXPECT_LT(m.angle_distortion_deg.max, 3.0);
    EXPECT_NEAR(m.conformal_ratio, 1.0, 0.005);
}

TEST(SphereKanai, SharedMeshesWithoutFlipsAndNearEightPi) {
    for (const char* name : {"hand.off", "bunny_small.obj", "blobby.off"}) {
        auto path = test::shared_mesh(name);
        if (!path) GTEST_SKIP() << "shared mesh " << name << " not found (set GIMG_MESH_DIR)";
        SCOPED_TRACE(name);
        const geo::Mesh mesh = geo::load_mesh(*path);
        const passes::SphereResult r = passes::sphere_kanai(mesh);
        EXPECT_TRUE(r.converged) << r.note;
        const passes::SphereMetrics m = passes::sphere_metrics(mesh, r.positions);
        EXPECT_EQ(m.flips, 0u);
        EXPECT_NEAR(m.conformal_ratio, 1.0, 0.02);
    }
}

TEST(SphereKanai, EnergyAtOrBelowGusWhereGuFinishes) {
    // Gu stops when a whole step changes F by less than 1e-5, so it ends a little above its
    // minimum; Kanai must not end above Gu.
    std::vector<std::pair<std::string, geo::Mesh>> cases{{"ellipsoid", ellipsoid(3)}};
    if (auto path = test::shared_mesh("blobby.off")) cases.emplace_back("blobby", geo::load_mesh(*path));
    for (const auto& [name, mesh] : cases) {
        SCOPED_TRACE(name);
        passes::GuOptions g;
        g.tutte_step = 0.05;
        g.conformal_step = 0.05;
        const passes::SphereResult gu = passes::sphere_gu(mesh, g);
        ASSERT_TRUE(gu.converged) << gu.note;
        const passes::SphereMetrics gm = passes::sphere_metrics(mesh, gu.positions);
        ASSERT_EQ(gm.flips, 0u);
        const passes::SphereMetrics km = passes::sphere_metrics(mesh, passes::sphere_kanai(mesh).positions);
        EXPECT_EQ(km.flips, 0u);
        EXPECT_LE(km.conformal_energy, gm.conformal_energy);
    }
}

TEST(SphereKanai, StagesFollowTheHierarchy) {
    const geo::Mesh e = ellipsoid(3);  // 642 vertices
    passes::KanaiOptions o;
    o.base_vertices = 100;
    std::size_t calls = 0;
    o.progress = [&](const std::string&, std::size_t, double, std::size_t flips, double) {
        ++calls;
        EXPECT_EQ(flips, 0u);
    };
    const passes::SphereResult r = passes::sphere_kanai(e, o);
    // progressive mesh, base map, then 200, 400, 642 vertices.
    ASSERT_EQ(r.stages.size(), 5u);
    EXPECT_EQ(r.stages[0].name, "progressive mesh");
    EXPECT_EQ(r.stages[1].name, "base map");
    EXPECT_EQ(r.stages[1].vertices, 100u);
    EXPECT_EQ(r.stages[2].vertices, 200u);
    EXPECT_EQ(r.stages[3].vertices, 400u);
    EXPECT_EQ(r.stages[4].vertices, 642u);
    for (std::size_t i = 2; i < r.stages.size(); ++i) {
        EXPECT_GT(r.stages[i].iterations, 0u) << r.stages[i].name;
        EXPECT_GT(r.stages[i].energy, 0.0);
    }
    EXPECT_NEAR(r.stages.back().energy, passes::sphere_metrics(e, r.positions).conformal_energy, 1e-9);
    EXPECT_GE(calls, 4u);
}

TEST(SphereKanai, AMeshSmallerThanTheBaseIsOptimisedOnce) {
    const geo::Mesh e = ellipsoid(1);  // 42 vertices
    const passes::SphereResult r = passes::sphere_kanai(e);
    ASSERT_EQ(r.stages.size(), 3u);
    EXPECT_EQ(r.stages.back().vertices, 42u);
    EXPECT_EQ(passes::sphere_metrics(e, r.positions).flips, 0u);
}

TEST(SphereKanai, RefusesWhatItCannotMap) {
    EXPECT_THROW(passes::sphere_kanai(geo::make_torus(2.0, 0.5, 12, 8)), geo::InputError);
    passes::KanaiOptions o;
    o.growth = 1.0;
    EXPECT_THROW(passes::sphere_kanai(geo::make_icosphere(1.0, 2), o), geo::InputError);
    o = {};
    o.queue_tolerance = 0.0;
    EXPECT_THROW(passes::sphere_kanai(geo::make_icosphere(1.0, 2), o), geo::InputError);
}

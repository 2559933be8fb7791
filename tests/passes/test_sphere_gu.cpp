// Gu et al.'s spherical parameterization (the CPU reference of the paper's chapter 3): right where
// it converges, and a plain failure report, not a hang, where its step constants do not fit.
#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/sphere.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <chrono>

using namespace gimg;

namespace {

passes::GuOptions steps(double tutte, double conformal) {
    passes::GuOptions o;
    o.tutte_step = tutte;
    o.conformal_step = conformal;
    return o;
}

}  // namespace

TEST(SphereGu, ASphereMapsToItself) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 3);
    const passes::SphereResult r = passes::sphere_gu(sphere, steps(0.1, 0.1));
    ASSERT_TRUE(r.converged) << r.note;
    ASSERT_EQ(r.stages.size(), 2u);
    EXPECT_EQ(r.stages[0].name, "tutte");
    EXPECT_EQ(r.stages[1].name, "conformal");
    EXPECT_GT(r.stages[1].iterations, 0u);
    const passes::SphereMetrics m = passes::sphere_metrics(sphere, r.positions);
    EXPECT_EQ(m.flips, 0u);
    EXPECT_LT(m.angle_distortion_deg.max, 0.5);
    EXPECT_NEAR(m.conformal_energy, r.stages[1].energy, 1e-9);
    // The Gauss map of a sphere is the sphere, and the mass-centre normalisation keeps it where it
    // is: the map is the identity, up to a rotation we did not ask for and do not get.
    double furthest = 0.0;
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v)
        furthest = std::max(furthest, glm::length(r.positions[v] - glm::normalize(sphere.positions[v])));
    EXPECT_LT(furthest, 0.02);
}

TEST(SphereGu, AnEllipsoidBecomesConformal) {
    geo::Mesh ellipsoid = geo::make_icosphere(1.0, 3);
    for (auto& p : ellipsoid.positions) p.y *= 2.0;
    const passes::SphereResult r = passes::sphere_gu(ellipsoid, steps(0.1, 0.1));
    ASSERT_TRUE(r.converged) << r.note;
    const passes::SphereMetrics m = passes::sphere_metrics(ellipsoid, r.positions);
    EXPECT_EQ(m.flips, 0u);
    EXPECT_LT(m.angle_distortion_deg.mean, 2.0);
    EXPECT_NEAR(m.conformal_ratio, 1.0, 0.01);
}

TEST(SphereGu, ATooLargeStepIsReportedNotLoopedOn) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 3);
    const auto t0 = std::chrono::steady_clock::now();
    const passes::SphereResult r = passes::sphere_gu(sphere, steps(5.0, 5.0));
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
    EXPECT_FALSE(r.converged);
    EXPECT_NE(r.note.find("diverged"), std::string::npos) << r.note;
    ASSERT_EQ(r.positions.size(), sphere.vertex_count());
    for (const glm::dvec3& p : r.positions) EXPECT_NEAR(glm::length(p), 1.0, 1e-9);  // the last finite iterate
}

TEST(SphereGu, TheIterationLimitIsReported) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 3);
    passes::GuOptions o = steps(1e-4, 1e-4);
    o.max_iterations = 10;
    std::size_t calls = 0;
    o.progress = [&](const std::string&, std::size_t, double, std::size_t, double) { ++calls; };
    const passes::SphereResult r = passes::sphere_gu(sphere, o);
    EXPECT_FALSE(r.converged);
    EXPECT_NE(r.note.find("iteration limit"), std::string::npos) << r.note;
    EXPECT_EQ(r.stages.back().iterations, 10u);
    EXPECT_GE(calls, 1u);
}

TEST(SphereGu, RefusesWhatItCannotMap) {
    EXPECT_THROW(passes::sphere_gu(geo::make_torus(2.0, 0.5, 12, 8)), geo::InputError);
    EXPECT_THROW(passes::sphere_gu(geo::make_icosphere(1.0, 1), steps(-1.0, 0.1)), geo::InputError);
    passes::GuOptions o;
    o.tolerance = 0.0;
    EXPECT_THROW(passes::sphere_gu(geo::make_icosphere(1.0, 1), o), geo::InputError);
}

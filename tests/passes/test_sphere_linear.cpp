// The `linear` spherical map (Choi, Lam & Lui): shapes whose conformal map is known in closed
// form, bad input, and the shared genus-0 meshes. No GPU.
//
// A conformal map of a closed genus-0 surface onto the sphere is unique only up to a Moebius
// transformation, and the method fixes that freedom by its own balancing rule, not by a rotation.
// So the known answers are compared through cross-ratios of four points, which every Moebius
// transformation keeps: they agree for two maps exactly when the maps differ by one.
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/sphere.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>

using namespace gimg;

namespace {

using Complex = std::complex<double>;

// Stereographic coordinate of unit vector p seen from -pole, in a right-handed frame around pole.
// Any such chart differs from another by a Moebius map, so cross-ratios do not depend on it.
Complex chart(const glm::dvec3& p, const glm::dvec3& pole) {
    const glm::dvec3 helper = std::abs(pole.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 e1 = glm::normalize(glm::cross(helper, pole));
    const glm::dvec3 e2 = glm::cross(pole, e1);
    return Complex(glm::dot(p, e1), glm::dot(p, e2)) / (1.0 + glm::dot(p, pole));
}

Complex cross_ratio(const glm::dvec3 p[4]) {
    const glm::dvec3 pole = glm::normalize(p[0] + p[1] + p[2] + p[3]);  // keeps the four away from infinity
    Complex z[4];
    for (int k = 0; k < 4; ++k) z[k] = chart(p[k], pole);
    return (z[0] - z[2]) * (z[1] - z[3]) / ((z[1] - z[2]) * (z[0] - z[3]));
}

// Largest |CR(a) / CR(b) - 1| over 300 fixed quadruples of vertices: 0 when the two sphere maps
// differ by an orientation-preserving Moebius transformation (a mirror image conjugates them).
double worst_cross_ratio_error(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
    double worst = 0.0;
    std::uint64_t state = 12345;
    auto next = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return std::size_t(state >> 33) % a.size();
    };
    for (int i = 0; i < 300; ++i) {
        const std::size_t v[4] = {next(), next(), next(), next()};
        const glm::dvec3 pa[4] = {a[v[0]], a[v[1]], a[v[2]], a[v[3]]};
        const glm::dvec3 pb[4] = {b[v[0]], b[v[1]], b[v[2]], b[v[3]]};
        if (v[0] == v[1] || v[0] == v[2] || v[0] == v[3] || v[1] == v[2] || v[1] == v[3] || v[2] == v[3]) continue;
        worst = std::max(worst, std::abs(cross_ratio(pa) / cross_ratio(pb) - 1.0));
    }
    return worst;
}

// The exact conformal map of the spheroid (x, b y, z), (x, y, z) on the unit sphere, onto the
// sphere: longitude kept, latitude changed so that the isothermal coordinate
// t = integral of sqrt(sin^2 u + b^2 cos^2 u) / cos u du matches the sphere's, atanh(sin).
// Written as atanh(sin beta) + a smooth remainder so no quadrature point meets the 1 / cos pole.
glm::dvec3 spheroid_to_sphere(const glm::dvec3& unit, double b) {
    const double beta = std::asin(std::clamp(unit.y, -1.0, 1.0));
    const int steps = 64;
    auto remainder = [b](double u) {
        const double c = std::cos(u);
        return (b * b - 1.0) * c / (std::sqrt(1.0 + (b * b - 1.0) * c * c) + 1.0);
    };
    double integral = remainder(0.0) + remainder(beta);
    for (int k = 1; k < steps; ++k) integral += (k % 2 ? 4.0 : 2.0) * remainder(beta * k / steps);
    integral *= beta / (3.0 * steps);
    const double t = std::atanh(unit.y) + integral;
    const double around = std::hypot(unit.x, unit.z);
    if (around == 0.0) return glm::dvec3(0.0, unit.y > 0.0 ? 1.0 : -1.0, 0.0);
    const double cos_lat = 1.0 / std::cosh(t);
    return glm::dvec3(cos_lat * unit.x / around, std::tanh(t), cos_lat * unit.z / around);
}

struct LinearRun {
    passes::SphereResult result;
    passes::SphereMetrics metrics;
    double seconds = 0.0;
};

LinearRun run_linear(const geo::Mesh& mesh) {
    LinearRun r;
    const auto start = std::chrono::steady_clock::now();
    r.result = passes::sphere_linear(mesh);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.metrics = passes::sphere_metrics(mesh, r.result.positions);
    return r;
}

void print_row(const std::string& name, const geo::Mesh& mesh, const LinearRun& r) {
    const auto& m = r.metrics;
    std::printf("%-16s %7zu %7zu %6zu  %8.5f  %6.3f %7.3f %8.3f  %6.3f  %s%s%s\n", name.c_str(), mesh.vertex_count(),
                mesh.face_count(), m.flips, m.conformal_ratio, m.angle_distortion_deg.mean, m.angle_distortion_deg.p95,
                m.angle_distortion_deg.max, r.seconds, r.result.converged ? "yes" : "NO",
                r.result.note.empty() ? "" : "  ", r.result.note.c_str());
}

void print_header() {
    std::printf("%-16s %7s %7s %6s  %8s  %6s %7s %8s  %6s  %s\n", "mesh", "verts", "faces", "flips", "F/8pi", "mean",
                "p95", "max deg", "sec", "converged");
}

}  // namespace

TEST(SphereLinear, ASphereMapsToItselfUpToAMoebiusMap) {
    const geo::Mesh s = geo::make_icosphere(1.0, 5);  // 10,242 vertices
    const LinearRun r = run_linear(s);
    print_header();
    print_row("icosphere 5", s, r);
    ASSERT_EQ(r.result.positions.size(), s.vertex_count());
    for (const auto& p : r.result.positions) ASSERT_NEAR(glm::length(p), 1.0, 1e-12);
    EXPECT_TRUE(r.result.converged) << r.result.note;
    EXPECT_TRUE(r.result.note.empty()) << r.result.note;
    ASSERT_EQ(r.result.stages.size(), 3u);
    for (const auto& stage : r.result.stages) {
        EXPECT_FALSE(stage.name.empty());
        EXPECT_EQ(stage.iterations, 0u);  // direct solves
    }

    // Measured: 0 flips, angle distortion mean 0.064, max 0.463 degrees (both halve with every
    // subdivision level: discretisation error), worst cross-ratio error 3.7e-3. Not a rotation,
    // though: the balancing leaves a Moebius stretch, which the print below shows.
    EXPECT_EQ(r.metrics.flips, 0u);
    EXPECT_LT(r.metrics.angle_distortion_deg.mean, 0.07);
    EXPECT_LT(r.metrics.angle_distortion_deg.max, 0.5);
    std::vector<glm::dvec3> identity;
    for (const auto& p : s.positions) identity.push_back(glm::normalize(p));
    const double cr = worst_cross_ratio_error(r.result.positions, identity);
    double stretch = 0.0;  // 0 for a rotation, which keeps every dot product
    for (std::size_t v = 1; v < identity.size(); v += 97)
        stretch = std::max(stretch, std::abs(glm::dot(identity[v], identity[v / 2]) -
                                             glm::dot(r.result.positions[v], r.result.positions[v / 2])));
    std::printf("worst cross-ratio error against the identity: %.2e; largest change of a dot product: %.3f\n", cr,
                stretch);
    EXPECT_LT(cr, 0.01);
}

// A prolate spheroid, the unit sphere stretched to twice its height: its conformal map onto the
// sphere is known in closed form (spheroid_to_sphere), so the test compares against the truth.
TEST(SphereLinear, AnEllipsoidMapsToItsExactConformalMap) {
    geo::Mesh e = geo::make_icosphere(1.0, 5);
    std::vector<glm::dvec3> exact, radial;
    for (auto& p : e.positions) {
        exact.push_back(spheroid_to_sphere(glm::normalize(p), 2.0));
        p.y *= 2.0;
        radial.push_back(glm::normalize(p));  // the naive map: straight out from the centre
    }
    const LinearRun r = run_linear(e);
    print_header();
    print_row("spheroid 1:2:1", e, r);
    const passes::SphereMetrics truth = passes::sphere_metrics(e, exact);
    const double cr_exact = worst_cross_ratio_error(r.result.positions, exact);
    const double cr_radial = worst_cross_ratio_error(r.result.positions, radial);
    std::printf(
        "exact conformal map: angle distortion mean %.3f max %.3f; worst cross-ratio error against it %.2e, "
        "against radial projection %.2e\n",
        truth.angle_distortion_deg.mean, truth.angle_distortion_deg.max, cr_exact, cr_radial);
    EXPECT_TRUE(r.result.converged) << r.result.note;
    // Measured: 0 flips; angle distortion mean 0.361, max 1.188 degrees, where the exact map itself
    // scores 0.324 and 0.801 (the metric compares flat mesh triangles with chord triangles, so even
    // the truth is not 0); cross-ratio error 3.9e-3 against the exact map, 0.48 against the radial
    // projection, so the test does tell the two apart.
    EXPECT_EQ(r.metrics.flips, 0u);
    EXPECT_LT(r.metrics.angle_distortion_deg.mean, truth.angle_distortion_deg.mean + 0.05);
    EXPECT_LT(r.metrics.angle_distortion_deg.max, 1.3);
    EXPECT_LT(cr_exact, 0.01);
    EXPECT_GT(cr_radial, 0.3);
}

TEST(SphereLinear, WrongTopologyIsRefused) {
    EXPECT_THROW(passes::sphere_linear(geo::make_torus(2.0, 0.5, 24, 12)), geo::InputError);
    EXPECT_THROW(passes::sphere_linear(geo::make_grid(8, 8)), geo::InputError);
    EXPECT_THROW(passes::sphere_linear(geo::Mesh{}), geo::InputError);
}

TEST(SphereLinear, BunnyIsConformalWithoutFlips) {
    GIMG_REQUIRE_SHARED_MESH(path, "bunny.off");
    const geo::Mesh mesh = geo::load_mesh(path);
    const LinearRun r = run_linear(mesh);
    print_header();
    print_row("bunny.off", mesh, r);
    EXPECT_TRUE(r.result.converged) << r.result.note;
    // Measured: 0 flips, F / 8 pi = 0.99933, angle distortion mean 1.112, p95 3.61, max 11.6 deg.
    EXPECT_EQ(r.metrics.flips, 0u);
    EXPECT_GT(r.metrics.conformal_ratio, 0.999);
    EXPECT_LT(r.metrics.conformal_ratio, 1.0);
    EXPECT_GT(r.metrics.angle_distortion_deg.mean, 1.08);
    EXPECT_LT(r.metrics.angle_distortion_deg.mean, 1.15);
    EXPECT_LT(r.metrics.angle_distortion_deg.p95, 3.8);
    EXPECT_LT(r.metrics.angle_distortion_deg.max, 13.0);
}

// The method's known weak spots, shown rather than hidden: long protrusions (camel's legs, the
// dinosaur's) are squeezed by any conformal map into regions below double precision, and obtuse
// triangles give negative cotangent weights. What is asserted is that every such case is reported:
// flips in the note, a failed solve as converged = false.
TEST(SphereLinear, SharedGenusZeroMeshesReportTheirFlips) {
    if (!gimg::test::mesh_dir()) GTEST_SKIP() << "shared meshes not found (set GIMG_MESH_DIR)";
    print_header();
    for (const char* name : {"bunny_small.obj", "blobby.off", "fandisk.off", "armadillo.off", "hand.off", "homer.off",
                             "triceratops.off", "cow.off", "dino.off", "camel.off"}) {
        const auto path = gimg::test::shared_mesh(name);
        if (!path) {
            std::printf("%-16s missing\n", name);
            continue;
        }
        const geo::Mesh mesh = geo::load_mesh(*path);
        const LinearRun r = run_linear(mesh);
        print_row(name, mesh, r);
        ASSERT_EQ(r.result.positions.size(), mesh.vertex_count()) << name;
        ASSERT_EQ(r.result.stages.size(), 3u) << name;
        if (r.metrics.flips) {
            EXPECT_NE(r.result.note.find("flipped"), std::string::npos) << name;
        }
        if (!r.result.converged) {
            EXPECT_FALSE(r.result.note.empty()) << name;
        }
        for (const auto& p : r.result.positions) ASSERT_NEAR(glm::length(p), 1.0, 1e-9) << name;
        // Smooth, protrusion-free shapes come out one-to-one (measured: 0 flips on these four).
        const std::string n = name;
        if (n == "bunny_small.obj" || n == "blobby.off" || n == "fandisk.off" || n == "armadillo.off") {
            EXPECT_EQ(r.metrics.flips, 0u) << name;
        }
    }
}

#include "gimg/geometry/pca.h"

#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include <random>

using namespace gimg::geo;

namespace {

glm::dmat3 rotation_about(glm::dvec3 axis, double angle) {
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis)));
}

Mesh transformed(const Mesh& m, const glm::dmat3& linear, glm::dvec3 offset) {
    Mesh out = m;
    for (auto& p : out.positions) p = linear * p + offset;
    return out;
}

double signed_volume(const Mesh& m) {
    double v = 0.0;
    for (const auto& t : m.triangles)
        v += glm::dot(m.positions[t.x], glm::cross(m.positions[t.y], m.positions[t.z])) / 6.0;
    return v;
}

// An egg-like closed surface with distinct extents (y 3, z 2, x 1) and skewed along y and z, so
// every principal axis and the skewness signs are well defined.
Mesh skewed_ellipsoid() {
    Mesh m = gimg::geo::make_uv_sphere(32, 16);
    for (auto& p : m.positions) {
        p *= glm::dvec3(1.0, 3.0, 2.0);
        p.y += 0.15 * p.y * p.y;
        p.z += 0.1 * p.z * p.z;
    }
    return m;
}

void expect_rotation(const glm::dmat3& r) {
    EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
    const glm::dmat3 rrt = r * glm::transpose(r);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(rrt[i][j], i == j ? 1.0 : 0.0, 1e-12);
}

}  // namespace

TEST(Pca, RotatedBoxComesBackAxisAlignedLongestSideAlongY) {
    const Mesh box = gimg::geo::make_box({1.0, 3.0, 2.0});
    const glm::dmat3 q = rotation_about({0.3, -1.0, 0.7}, 1.1);
    const glm::dvec3 offset(5.0, -2.0, 0.25);
    const Mesh input = transformed(box, q, offset);
    for (auto weighting : {PcaWeighting::Vertices, PcaWeighting::SurfaceArea}) {
        const PcaAlignment pca = compute_pca_alignment(input, weighting);
        expect_rotation(pca.transform.rotation);
        EXPECT_NEAR(glm::length(pca.centroid - offset), 0.0, 1e-12);
        const Mesh aligned = pca.transform.apply(input);
        // Longest side (3) along y, second (2) along x, shortest (1) along z.
        for (const auto& p : aligned.positions) {
            EXPECT_NEAR(std::abs(p.x), 1.0, 1e-12);
            EXPECT_NEAR(std::abs(p.y), 1.5, 1e-12);
            EXPECT_NEAR(std::abs(p.z), 0.5, 1e-12);
        }
        EXPECT_NEAR(signed_volume(aligned), signed_volume(input), 1e-12);
        // Back to the input frame.
        const Mesh back = pca.transform.inverse().apply(aligned);
        for (std::size_t v = 0; v < input.vertex_count(); ++v)
            EXPECT_NEAR(glm::length(back.positions[v] - input.positions[v]), 0.0, 1e-12);
    }
}

TEST(Pca, VarianceOfBoxVerticesAndOfBoxSurface) {
    const double a = 1.0, b = 3.0, c = 2.0;
    const Mesh box = gimg::geo::make_box({a, b, c});
    const PcaAlignment vertices = compute_pca_alignment(box, PcaWeighting::Vertices);
    EXPECT_NEAR(vertices.variances.x, b * b / 4, 1e-12);  // main
    EXPECT_NEAR(vertices.variances.y, c * c / 4, 1e-12);  // second
    EXPECT_NEAR(vertices.variances.z, a * a / 4, 1e-12);  // third
    // Uniform density on the surface: the two faces across an axis sit at +-s/2, the other four
    // spread uniformly along it (variance s^2 / 12).
    const double area = 2 * (a * b + b * c + c * a);
    auto surface_variance = [&](double s, double across, double along) {
        return (across * s * s / 4 + along * s * s / 12) / area;
    };
    const PcaAlignment surface = compute_pca_alignment(box, PcaWeighting::SurfaceArea);
    EXPECT_NEAR(surface.variances.x, surface_variance(b, 2 * a * c, 2 * (a * b + b * c)), 1e-12);
    EXPECT_NEAR(surface.variances.y, surface_variance(c, 2 * a * b, 2 * (a * c + b * c)), 1e-12);
    EXPECT_NEAR(surface.variances.z, surface_variance(a, 2 * b * c, 2 * (a * b + a * c)), 1e-12);
}

TEST(Pca, AlignedPoseDoesNotDependOnTheInputPose) {
    const Mesh egg = skewed_ellipsoid();
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (auto weighting : {PcaWeighting::Vertices, PcaWeighting::SurfaceArea}) {
        const Mesh reference = compute_pca_alignment(egg, weighting).transform.apply(egg);
        // The skew along y: the egg's wide end (+y after p.y += 0.15 y^2) ...
        double m3 = 0.0;
        for (const auto& p : reference.positions) m3 += p.y * p.y * p.y;
        EXPECT_GT(m3, 0.0);
        for (int trial = 0; trial < 8; ++trial) {
            const glm::dmat3 q = rotation_about({u(rng), u(rng), u(rng)}, 3.0 * u(rng));
            const Mesh input = transformed(egg, q, {10 * u(rng), 10 * u(rng), 10 * u(rng)});
            const PcaAlignment pca = compute_pca_alignment(input, weighting);
            expect_rotation(pca.transform.rotation);
            const Mesh aligned = pca.transform.apply(input);
            for (std::size_t v = 0; v < egg.vertex_count(); ++v)
                ASSERT_NEAR(glm::length(aligned.positions[v] - reference.positions[v]), 0.0, 1e-9)
                    << "trial " << trial << " vertex " << v;
        }
    }
}

TEST(Pca, MirroredInputIsNeverMirroredBack) {
    // A reflection of the input (det -1) must come out as the reflection of the canonical pose
    // across the xy plane: the main and second axes follow their skew, and the third axis is
    // their cross product, which a rotation can never turn into a reflection.
    const Mesh egg = skewed_ellipsoid();
    const Mesh reference = compute_pca_alignment(egg).transform.apply(egg);
    const glm::dmat3 mirror =
        rotation_about({1, 2, 3}, 0.8) * glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));
    ASSERT_NEAR(glm::determinant(mirror), -1.0, 1e-12);
    Mesh input = transformed(egg, mirror, {1, 2, 3});
    for (auto& t : input.triangles) std::swap(t.y, t.z);  // keep the faces outward
    const PcaAlignment pca = compute_pca_alignment(input);
    expect_rotation(pca.transform.rotation);
    const Mesh aligned = pca.transform.apply(input);
    for (std::size_t v = 0; v < egg.vertex_count(); ++v) {
        const glm::dvec3 expected = reference.positions[v] * glm::dvec3(1, 1, -1);
        ASSERT_NEAR(glm::length(aligned.positions[v] - expected), 0.0, 1e-9) << "vertex " << v;
    }
    EXPECT_GT(signed_volume(aligned), 0.0);  // still outward: not turned inside out
}

TEST(Pca, DegenerateInputsGiveIdentityRotation) {
    EXPECT_EQ(compute_pca_alignment(Mesh{}).transform.rotation, glm::dmat3(1.0));
    Mesh point;
    point.positions = {{1, 2, 3}, {1, 2, 3}, {1, 2, 3}};
    point.triangles = {{0, 1, 2}};
    for (auto weighting : {PcaWeighting::Vertices, PcaWeighting::SurfaceArea}) {
        const PcaAlignment pca = compute_pca_alignment(point, weighting);
        EXPECT_EQ(pca.transform.rotation, glm::dmat3(1.0));
        EXPECT_EQ(pca.transform.apply_point({1, 2, 3}), glm::dvec3(0.0));
    }
}

TEST(RigidTransform, InverseAndComposition) {
    RigidTransform t{rotation_about({1, 1, 0}, 0.7), {1, -2, 3}};
    const RigidTransform s{rotation_about({0, 0, 1}, -1.3), {0.5, 0, 0}};
    const glm::dvec3 p(0.3, 0.4, -5);
    EXPECT_NEAR(glm::length(t.inverse().apply_point(t.apply_point(p)) - p), 0.0, 1e-14);
    EXPECT_NEAR(glm::length(s.after(t).apply_point(p) - s.apply_point(t.apply_point(p))), 0.0, 1e-14);
    EXPECT_NEAR(glm::length(t.apply_vector(p) - t.rotation * p), 0.0, 0.0);
}

#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/geometry/surface_sampling.h"

#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace gimg::geo;

namespace {

SurfaceDistanceOptions with_samples(std::size_t n) {
    SurfaceDistanceOptions o;
    o.sampling.sample_count = n;
    return o;
}

// How far an inscribed sphere mesh (vertices at radius r around c) dips inside the sphere:
// r minus the smallest distance from c to a face plane.
double sagitta(const Mesh& m, double r, glm::dvec3 c) {
    double closest = r;
    for (const auto& t : m.triangles) {
        const glm::dvec3 a = m.positions[t.x], b = m.positions[t.y], d = m.positions[t.z];
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, d - a));
        closest = std::min(closest, std::abs(glm::dot(a - c, n)));
    }
    return r - closest;
}

}  // namespace

TEST(SurfaceSampling, CountsFollowTheRule) {
    SurfaceSamplingOptions o;
    EXPECT_EQ(resolve_sample_count(o, 50'000), 1'000'000u);
    EXPECT_EQ(resolve_sample_count(o, 300'000), 3'000'000u);
    o.sample_count = 1234;
    EXPECT_EQ(resolve_sample_count(o, 300'000), 1234u);

    const std::vector<double> areas = {0.5, 0.0, 2.25, 1e-9, 0.75, 0.0, 3.1};
    double total_area = 0.0;
    for (double a : areas) total_area += a;
    for (std::uint64_t seed : {1ull, 2ull, 99ull}) {
        const auto counts = face_sample_counts(areas, 1001, seed);
        std::size_t sum = 0;
        for (std::size_t f = 0; f < areas.size(); ++f) {
            const double expected = 1001 * areas[f] / total_area;
            EXPECT_GE(double(counts[f]), std::floor(expected) - 1e-9);
            EXPECT_LE(double(counts[f]), std::ceil(expected) + 1e-9);
            if (areas[f] == 0.0) {
                EXPECT_EQ(counts[f], 0u);
            }
            sum += counts[f];
        }
        EXPECT_EQ(sum, 1001u);
    }
}

TEST(SurfaceSampling, UniformByAreaAndOnTheSurface) {
    // The unit square as a fan around an off-centre point: triangles of very different areas.
    Mesh m;
    m.positions = {{0.9, 0.15, 0}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
    SurfaceSamplingOptions o;
    o.sample_count = 200'000;
    const auto samples = sample_surface(m, o);
    ASSERT_EQ(samples.size(), 200'000u);
    glm::dvec3 mean(0.0);
    std::size_t left = 0, bottom_left_quarter = 0;
    for (const auto& p : samples) {
        ASSERT_EQ(p.z, 0.0);
        ASSERT_TRUE(p.x >= 0.0 && p.x <= 1.0 && p.y >= 0.0 && p.y <= 1.0);
        mean += p;
        left += p.x < 0.5;
        bottom_left_quarter += p.x < 0.5 && p.y < 0.5;
    }
    mean /= double(samples.size());
    // Uniform on the square: centroid (0.5, 0.5), half the points left of x = 0.5, a quarter in
    // [0, 0.5)^2. Independent uniform samples would be off by ~1e-3 (1/sqrt(N)); stratified ones
    // do better, so 1e-3 is a real bound here, not a loose one.
    EXPECT_NEAR(mean.x, 0.5, 1e-3);
    EXPECT_NEAR(mean.y, 0.5, 1e-3);
    EXPECT_NEAR(double(left) / double(samples.size()), 0.5, 1e-3);
    EXPECT_NEAR(double(bottom_left_quarter) / double(samples.size()), 0.25, 1e-3);

    EXPECT_EQ(sample_surface(m, o), samples);  // deterministic
    o.seed += 1;
    EXPECT_NE(sample_surface(m, o), samples);
}

TEST(SurfaceDistance, ConcentricSpheres) {
    // Different tessellations, so no sample lines up with a vertex of the other mesh. Both meshes
    // are inscribed in their spheres, dipping inside by at most their sagitta s_in, s_out, so
    // every distance, either way, lies in [0.1 - s_out, 0.1 + s_in + s_out]; the meshes are fine
    // enough for that interval to sit inside 0.1 +- 1 %.
    const Mesh inner = gimg::geo::make_icosphere(1.0, 5);
    const Mesh outer = gimg::geo::make_uv_sphere(256, 128, 1.1);
    const double s_in = sagitta(inner, 1.0, glm::dvec3(0.0)), s_out = sagitta(outer, 1.1, glm::dvec3(0.0));
    ASSERT_LT(s_in + s_out, 1e-3);
    const SurfaceDistance d = surface_distance(inner, outer, with_samples(200'000));
    for (const DistanceStats* s : {&d.a_to_b, &d.b_to_a, &d.symmetric})
        for (double value : {s->mean, s->rms, s->max}) {
            EXPECT_GE(value, 0.1 - s_out);
            EXPECT_LE(value, 0.1 + s_in + s_out);
            EXPECT_NEAR(value, 0.1, 1e-3);
        }
    EXPECT_EQ(d.a_to_b.samples, 200'000u);
    EXPECT_EQ(d.symmetric.samples, 400'000u);
    EXPECT_NEAR(d.bbox_diagonal, 2.0 * std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(d.relative(d.symmetric).mean, d.symmetric.mean / d.bbox_diagonal, 1e-15);
    // The symmetric figures are those of the union of both sample sets.
    EXPECT_NEAR(d.symmetric.mean, (d.a_to_b.mean + d.b_to_a.mean) / 2, 1e-15);
    EXPECT_NEAR(d.symmetric.rms, std::sqrt((d.a_to_b.rms * d.a_to_b.rms + d.b_to_a.rms * d.b_to_a.rms) / 2), 1e-15);
    EXPECT_EQ(d.symmetric.max, std::max(d.a_to_b.max, d.b_to_a.max));
}

TEST(SurfaceDistance, MeshAgainstItselfIsZero) {
    const Mesh m = gimg::geo::make_uv_sphere(60, 30, 3.0);
    const SurfaceDistance d = surface_distance(m, m, with_samples(100'000));
    for (const DistanceStats* s : {&d.a_to_b, &d.b_to_a, &d.symmetric}) {
        EXPECT_LE(s->mean, 1e-12);
        EXPECT_LE(s->rms, 1e-12);
        EXPECT_LE(s->max, 1e-12);
    }
}

TEST(SurfaceDistance, TranslatedSphere) {
    // B = A + t. Every point p of A has p + t on B, so no distance exceeds |t| (exactly true for
    // any surface). For the exact unit sphere, the point with unit direction u is at distance
    // f(c) = |1 - sqrt(1 - 2|t|c + |t|^2)|, c = u.t/|t| uniform in [-1, 1]; max f = |t|.
    // The meshes are inscribed with sagitta s, so each sample's distance is within 2s of f at
    // its direction (s to move the sample onto its sphere, s for B's mesh against B's sphere),
    // and mean and RMS are within 2s of the sphere's (plus O(s * f) from the mesh's area
    // element, negligible here).
    const glm::dvec3 t(0.03, -0.04, 0.0);
    const double len = glm::length(t);
    const Mesh a = gimg::geo::make_icosphere(1.0, 5);
    Mesh b = a;
    for (auto& p : b.positions) p += t;
    const double s = sagitta(a, 1.0, glm::dvec3(0.0));
    ASSERT_LT(s, 3e-4);

    const int n = 200'000;
    double mean = 0.0, mean_sq = 0.0;
    for (int i = 0; i < n; ++i) {
        const double c = -1.0 + (i + 0.5) * 2.0 / n;
        const double f = std::abs(1.0 - std::sqrt(1.0 - 2.0 * len * c + len * len));
        mean += f / n;
        mean_sq += f * f / n;
    }
    const double rms = std::sqrt(mean_sq);

    const SurfaceDistance d = surface_distance(a, b, with_samples(200'000));
    for (const DistanceStats* st : {&d.a_to_b, &d.b_to_a}) {
        EXPECT_LE(st->max, len * (1 + 1e-12));
        EXPECT_GE(st->max, 0.9 * len);
        EXPECT_NEAR(st->mean, mean, 2 * s);
        EXPECT_NEAR(st->rms, rms, 2 * s);
    }
    std::printf("translated sphere: mean %.6f (sphere %.6f), rms %.6f (%.6f), max %.6f (|t| %.6f), 2s %.6f\n",
                d.a_to_b.mean, mean, d.a_to_b.rms, rms, d.a_to_b.max, len, 2 * s);
}

TEST(SurfaceDistance, SameBitsForAnyThreadCount) {
    const Mesh a = gimg::geo::make_icosphere(1.0, 3);
    const Mesh b = gimg::geo::make_uv_sphere(40, 20, 1.05);
    SurfaceDistanceOptions o = with_samples(50'000);
    o.threads = 1;
    const SurfaceDistance one = surface_distance(a, b, o);
    for (unsigned threads : {2u, 3u, 8u}) {
        o.threads = threads;
        const SurfaceDistance many = surface_distance(a, b, o);
        EXPECT_EQ(many.a_to_b.mean, one.a_to_b.mean);
        EXPECT_EQ(many.a_to_b.rms, one.a_to_b.rms);
        EXPECT_EQ(many.a_to_b.max, one.a_to_b.max);
        EXPECT_EQ(many.b_to_a.mean, one.b_to_a.mean);
        EXPECT_EQ(many.symmetric.rms, one.symmetric.rms);
    }
}

TEST(SurfaceDistance, MaximumIncludesTheVertices) {
    // A coarse icosahedron of radius 1.2 around a fine unit sphere: its farthest points from the
    // sphere are its 12 corners (distance 0.2 + at most the fine mesh's sagitta), which area
    // samples practically never hit. The reported max includes them; the samples alone fall short.
    const Mesh coarse = gimg::geo::make_icosphere(1.2, 0);
    const Mesh fine = gimg::geo::make_icosphere(1.0, 5);
    const double s = sagitta(fine, 1.0, glm::dvec3(0.0));
    const TriangleBvh bvh(fine);
    SurfaceDistanceOptions o = with_samples(2000);
    const DistanceStats d = one_sided_distance(coarse, bvh, o);
    EXPECT_GE(d.max, 0.2 - 1e-12);
    EXPECT_LE(d.max, 0.2 + s);
    double sampled_max = 0.0;
    for (const auto& p : sample_surface(coarse, o.sampling))
        sampled_max = std::max(sampled_max, bvh.closest_point(p).distance);
    EXPECT_LT(sampled_max, 0.2 - 1e-3);
    EXPECT_LT(sampled_max, d.max);
}

TEST(SurfaceDistance, RejectsSurfacesWithoutArea) {
    Mesh flat;
    flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    flat.triangles = {{0, 1, 2}};
    const Mesh s = gimg::geo::make_icosphere(1.0, 1);
    EXPECT_THROW(surface_distance(flat, s), InputError);
    EXPECT_THROW(surface_distance(s, flat), InputError);
    EXPECT_THROW(surface_distance(Mesh{}, s), InputError);
}

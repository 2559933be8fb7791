// Meshes into position geometry images: a planar grid with identity parameters reproduces its
// positions; GPU and CPU agree; sampling then reconstructing stays close to the original.
#include "gpu_test.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/passes/reconstruct.h"
#include "gimg/passes/sample.h"

#include <cmath>
#include <numbers>

using namespace gimg;

namespace {

class Sample : public gimg::test::GpuTest {};

// A grid bent into a half cylinder of radius 1 (parameters stay those of the flat grid).
geo::Mesh half_cylinder(int n) {
    geo::Mesh m = geo::make_grid(n, n, 1.0, 1.0);
    for (auto& p : m.positions) {
        const double a = std::numbers::pi * p.x;
        p = {std::cos(a), p.y, std::sin(a)};
    }
    return m;
}

}  // namespace

TEST_F(Sample, PlanarGridWithIdentityParametersReproducesItsPositions) {
    const geo::Mesh grid = geo::make_grid(7, 5, 1.0, 1.0);  // positions (s, t, 0), parameters (s, t)
    const std::uint32_t N = 64;
    for (const bool gpu : {false, true}) {
        const passes::PositionImage img = gpu ? passes::sample_gpu(ctx(), grid, N) : passes::sample_cpu(grid, N);
        for (std::uint32_t j = 0; j < N; ++j)
            for (std::uint32_t i = 0; i < N; ++i) {
                const std::size_t o = img.index(i, j);
                ASSERT_TRUE(img.covered[o]) << (gpu ? "gpu " : "cpu ") << i << "," << j;
                ASSERT_NEAR(img.xyz[3 * o], (i + 0.5) / N, 1e-6) << (gpu ? "gpu" : "cpu");
                ASSERT_NEAR(img.xyz[3 * o + 1], 1.0 - (j + 0.5) / N, 1e-6) << (gpu ? "gpu" : "cpu");
                ASSERT_EQ(img.xyz[3 * o + 2], 0.0f);
            }
    }
}

TEST_F(Sample, GpuEqualsCpuOnACurvedSurfaceWithAHole) {
    geo::Mesh m = half_cylinder(24);
    // Cut a hole: drop the faces whose parameters lie in the middle square.
    std::vector<glm::uvec3> kept;
    for (const auto& t : m.triangles) {
        const glm::dvec2 c = (m.texcoords[t.x] + m.texcoords[t.y] + m.texcoords[t.z]) / 3.0;
        if (!(std::abs(c.x - 0.5) < 0.2 && std::abs(c.y - 0.5) < 0.2)) kept.push_back(t);
    }
    m.triangles = kept;
    const std::uint32_t N = 100;
    const passes::PositionImage gpu = passes::sample_gpu(ctx(), m, N), cpu = passes::sample_cpu(m, N);
    std::size_t covered = 0, differ = 0;
    double worst = 0.0;
    for (std::size_t o = 0; o < gpu.covered.size(); ++o) {
        covered += cpu.covered[o];
        if (gpu.covered[o] != cpu.covered[o]) {
            ++differ;  // only where a pixel centre lies on the hole's edge
            continue;
        }
        if (!cpu.covered[o]) continue;
        for (int k = 0; k < 3; ++k) worst = std::max(worst, double(std::abs(gpu.xyz[3 * o + k] - cpu.xyz[3 * o + k])));
    }
    EXPECT_GT(covered, N * N * 3 / 4);
    EXPECT_LT(covered, N * N);  // the hole is empty
    EXPECT_LE(differ, std::size_t(N));
    EXPECT_LT(worst, 1e-5);
}

TEST_F(Sample, SampledThenReconstructedStaysCloseToTheOriginal) {
    const geo::Mesh m = half_cylinder(32);
    const passes::PositionImage img = passes::sample_gpu(ctx(), m, 256);
    const geo::Mesh back = passes::reconstruct_gpu(ctx(), img);
    EXPECT_EQ(back.face_count(), 2u * 255u * 255u);
    geo::SurfaceDistanceOptions o;
    o.sampling.sample_count = 200000;
    const geo::SurfaceDistance d = geo::surface_distance(m, back, o);
    // Its vertices lie on the original's facets; a triangle bridging a crease (facets meet at
    // pi/32) sags off it by at most its size (a pixel's 3D diagonal, hypot(pi, 1) / 256) times
    // sin(pi/64): 6.4e-4.
    const double bridge = std::hypot(std::numbers::pi, 1.0) / 256.0 * std::sin(std::numbers::pi / 64.0);
    EXPECT_LT(d.b_to_a.max, bridge);
    EXPECT_LT(d.symmetric.rms, 1e-3 * d.bbox_diagonal);
}

TEST_F(Sample, MeshesWithoutParametersAreRefused) {
    EXPECT_THROW(passes::sample_gpu(ctx(), geo::make_icosphere(1.0, 1), 16), geo::InputError);
    EXPECT_THROW(passes::sample_cpu(geo::make_icosphere(1.0, 1), 16), geo::InputError);
}

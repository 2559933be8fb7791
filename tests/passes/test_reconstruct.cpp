// Geometry images back to meshes: analytic images recover analytic surfaces; the GPU path equals
// the CPU reference vertex for vertex and triangle for triangle; occlusions become holes, not lace.
#include "cylinder_cases.h"
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/reconstruct.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>

using namespace gimg;
using gimg::test::theta_of;
using gimg::test::y_of;

namespace {

class Reconstruct : public gimg::test::GpuTest, public ::testing::WithParamInterface<bool> {
protected:
    // GetParam(): true for the GPU path.
    geo::Mesh rebuild(const passes::CylinderImage& image, const passes::CylinderFrame& frame,
                      const passes::ReconstructOptions& options = {}, passes::ReconstructStats* stats = nullptr) {
        return GetParam() ? passes::reconstruct_gpu(ctx(), image, frame, options, stats)
                          : passes::reconstruct_cpu(image, frame, options, stats);
    }
};

// d(u, v) of the image of a shape given its distance along each pixel's line.
template <class Distance>
passes::CylinderImage analytic_image(std::uint32_t w, std::uint32_t h, Distance&& distance) {
    passes::CylinderImage img(w, h);
    for (std::uint32_t v = 0; v < h; ++v)
        for (std::uint32_t u = 0; u < w; ++u) {
            const double d = distance(theta_of(u, w), y_of(v, h));
            if (std::isnan(d)) continue;
            img.covered[img.index(u, v)] = 1;
            img.distance[img.index(u, v)] = float(d);
        }
    return img;
}

}  // namespace

TEST_P(Reconstruct, CentredSphereImageGivesVerticesAtRadiusR) {
    const double r = 0.4, y0 = 0.5;
    const auto image = analytic_image(256, 128, [&](double, double y) {
        const double dy = y - y0;
        return std::abs(dy) < r ? std::sqrt(r * r - dy * dy) : std::numeric_limits<double>::quiet_NaN();
    });
    const geo::Mesh mesh = rebuild(image, passes::CylinderFrame{});
    ASSERT_GT(mesh.vertex_count(), 256u * 100u);
    ASSERT_GT(mesh.face_count(), 2u * 256u * 90u);
    for (const auto& p : mesh.positions) ASSERT_NEAR(glm::length(p - glm::dvec3(0, y0, 0)), r, 1e-5);
    // Every triangle faces away from the centre (seen from the wall: outwards).
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
        ASSERT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0 - glm::dvec3(0, y0, 0)), 0.0);
    }
    ASSERT_TRUE(mesh.has_normals());
}

TEST_P(Reconstruct, CubeImageGivesVerticesOnTheCubeAndCapsCloseIt) {
    const double a = 0.3;
    const auto image = analytic_image(360, 90, [&](double th, double y) {
        return y > 0.3 && y < 0.7 ? a / std::max(std::abs(std::cos(th)), std::abs(std::sin(th)))
                                  : std::numeric_limits<double>::quiet_NaN();
    });
    passes::ReconstructOptions o;
    o.fill_caps = true;
    const geo::Mesh mesh = rebuild(image, passes::CylinderFrame{}, o);
    std::size_t on_sides = 0;
    for (const auto& p : mesh.positions)
        if (std::abs(std::max(std::abs(p.x), std::abs(p.z)) - a) < 1e-6) ++on_sides;
    EXPECT_EQ(on_sides, mesh.vertex_count() - 2);  // all but the two cap centres
    // With caps the surface is closed and consistently oriented: every directed edge once, and
    // its reverse once.
    std::map<std::pair<unsigned, unsigned>, int> edges;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : edges) {
        ASSERT_EQ(n, 1) << e.first << "->" << e.second;
        ASSERT_EQ(edges.count({e.second, e.first}), 1u) << e.first << "->" << e.second << " has no twin";
    }
}

TEST_P(Reconstruct, OcclusionsBecomeHolesAtTheDefaultThresholdAndLaceWithoutOne) {
    // Two walls at radius 0.8 and 0.3, the near one covering half the turn: where it ends, the
    // line jumps from one to the other.
    const auto image = analytic_image(200, 100, [](double th, double y) {
        if (y < 0.1 || y > 0.9) return std::numeric_limits<double>::quiet_NaN();
        return th < 3.14159 ? 0.8 : 0.3;
    });
    passes::ReconstructStats stats;
    const geo::Mesh holes = rebuild(image, passes::CylinderFrame{}, {}, &stats);
    EXPECT_GT(stats.holes, 0u);
    passes::ReconstructOptions off;
    off.threshold = std::numeric_limits<float>::infinity();
    const geo::Mesh lace = rebuild(image, passes::CylinderFrame{}, off);
    EXPECT_EQ(lace.face_count(), holes.face_count() + 2 * stats.holes);
    auto longest_edge = [](const geo::Mesh& m) {
        double worst = 0.0;
        for (const auto& t : m.triangles)
            for (int k = 0; k < 3; ++k)
                worst = std::max(worst, glm::length(m.positions[t[k]] - m.positions[t[(k + 1) % 3]]));
        return worst;
    };
    EXPECT_LT(longest_edge(holes), 0.1);  // nothing spans the jump
    EXPECT_GT(longest_edge(lace), 0.45);  // the connecting faces of the paper's fig. 2.11
}

TEST_P(Reconstruct, LevelOfDetailHalvesTheImageWithoutMixingEmptyPixels) {
    const double r = 0.4, y0 = 0.5;
    const auto image = analytic_image(256, 128, [&](double, double y) {
        const double dy = y - y0;
        return std::abs(dy) < r ? std::sqrt(r * r - dy * dy) : std::numeric_limits<double>::quiet_NaN();
    });
    passes::ReconstructOptions o;
    o.lod = 2;
    passes::ReconstructStats stats;
    const geo::Mesh mesh = rebuild(image, passes::CylinderFrame{}, o, &stats);
    EXPECT_EQ(stats.width, 64u);
    EXPECT_EQ(stats.height, 32u);
    // Averages of points on the sphere lie just inside it, never out at an empty pixel's 0.
    for (const auto& p : mesh.positions) {
        const double dist = glm::length(p - glm::dvec3(0, y0, 0));
        ASSERT_LE(dist, r + 1e-5);
        ASSERT_GT(dist, 0.95 * r);
    }
    EXPECT_THROW(rebuild(passes::CylinderImage(100, 50), passes::CylinderFrame{}, o), geo::InputError);
}

INSTANTIATE_TEST_SUITE_P(Paths, Reconstruct, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& p) { return std::string(p.param ? "gpu" : "cpu"); });

class ReconstructMeshes : public gimg::test::GpuTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(ReconstructMeshes, GpuEqualsCpuVertexForVertex) {
    GIMG_REQUIRE_SHARED_MESH(path, GetParam());
    const geo::Mesh mesh = geo::load_mesh(path);
    const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
    const auto size = passes::auto_cylinder_size(mesh.face_count());
    const auto image = passes::cylinder_scanline(passes::make_cylinder_mesh(mesh, frame), 2 * size[0], 2 * size[1]);
    for (std::uint32_t lod : {0u, 1u}) {
        for (bool caps : {false, true}) {
            passes::ReconstructOptions o;
            o.lod = lod;
            o.fill_caps = caps;
            passes::ReconstructStats cs, gs;
            const geo::Mesh cpu = passes::reconstruct_cpu(image, frame, o, &cs);
            const geo::Mesh gpu = passes::reconstruct_gpu(ctx(), image, frame, o, &gs);
            ASSERT_EQ(cpu.positions, gpu.positions) << "lod " << lod;
            ASSERT_EQ(cpu.triangles, gpu.triangles) << "lod " << lod;
            EXPECT_EQ(cs.holes, gs.holes);
            EXPECT_GT(cpu.face_count(), std::size_t(size[0]) * size[1] / 4);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, ReconstructMeshes,
                         ::testing::Values("armadillo.off", "bunny.off", "cow.off", "teapot.obj", "dragon_res4.ply"),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                             std::string name = p.param;
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

// The GPU Z-buffer (its default split between compute and graphics pipeline, each of the two
// alone, and its float32 path) and the paper's scanline method against the CPU ray caster on real
// meshes at several sizes: the same covered pixels except at most 0.05 % (ties on silhouettes),
// |delta d| <= 1e-5 everywhere both cover (float32: 5e-5).
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/io.h"
#include "gimg/passes/cylinder.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

using namespace gimg;

namespace {

class CylinderMeshes : public gimg::test::GpuTest, public ::testing::WithParamInterface<const char*> {};

struct Agreement {
    std::size_t covered = 0, coverage_mismatch = 0;
    double max_abs_difference = 0.0;
};

Agreement compare(const passes::CylinderImage& a, const passes::CylinderImage& b) {
    Agreement r;
    for (std::size_t i = 0; i < a.covered.size(); ++i) {
        if (a.covered[i] || b.covered[i]) ++r.covered;
        if (a.covered[i] != b.covered[i]) {
            ++r.coverage_mismatch;
        } else if (a.covered[i]) {
            r.max_abs_difference = std::max(r.max_abs_difference, double(std::abs(a.distance[i] - b.distance[i])));
        }
    }
    return r;
}

using Size = std::array<std::uint32_t, 2>;

// A shared mesh in the cylinder frame, and the sizes every test here projects it at.
struct MeshCase {
    passes::CylinderMesh cyl;
    std::vector<Size> sizes;
};

MeshCase load_case(const std::string& path) {
    const geo::Mesh mesh = geo::load_mesh(path);
    const auto auto_size = passes::auto_cylinder_size(mesh.face_count());
    return {passes::make_cylinder_mesh(mesh, passes::fit_cylinder_frame(mesh)),
            {{64, 32}, {200, 100}, {540, 270}, {auto_size[0], auto_size[1]}}};
}

// One method's image against the ray caster's: reported, and held to the bars.
void expect_agreement(const std::string& label, Size size, const passes::CylinderImage& image,
                      const passes::CylinderImage& cpu, double max_difference) {
    const Agreement r = compare(image, cpu);
    std::printf("%s %ux%u: %zu covered, %zu coverage mismatches, max |delta d| %.3g\n", label.c_str(), size[0], size[1],
                r.covered, r.coverage_mismatch, r.max_abs_difference);
    EXPECT_GT(r.covered, std::size_t(size[0]) * size[1] / 10) << label;
    EXPECT_LE(double(r.coverage_mismatch), 0.0005 * double(r.covered)) << label << " " << size[0] << "x" << size[1];
    EXPECT_LE(r.max_abs_difference, max_difference) << label << " " << size[0] << "x" << size[1];
}

}  // namespace

TEST_P(CylinderMeshes, ZBufferAndScanlineEqualRaycast) {
    GIMG_REQUIRE_SHARED_MESH(path, GetParam());
    const MeshCase c = load_case(path);
    const passes::CylinderMesh& cyl = c.cyl;
    for (const Size& size : c.sizes) {
        using passes::CylinderLargePieces;
        passes::CylinderZBuffer z(ctx(), size[0], size[1]);
        const auto gpu = z.project(z.add_mesh(cyl));
        // The default split with large pieces through the graphics pipeline (what GPUs run), every
        // piece there, every piece in the classify pass, every piece in the large-piece compute pass.
        passes::CylinderZBuffer split(ctx(), size[0], size[1], {.large_pieces = CylinderLargePieces::Graphics});
        const auto gpu_split = split.project(split.add_mesh(cyl));
        passes::CylinderZBuffer graphics(ctx(), size[0], size[1],
                                         {.small_pixels = 0, .large_pieces = CylinderLargePieces::Graphics});
        const auto gpu_graphics = graphics.project(graphics.add_mesh(cyl));
        passes::CylinderZBuffer compute(ctx(), size[0], size[1], {.small_pixels = UINT32_MAX});
        const auto gpu_compute = compute.project(compute.add_mesh(cyl));
        passes::CylinderZBuffer large(ctx(), size[0], size[1],
                                      {.small_pixels = 0, .large_pieces = CylinderLargePieces::Compute});
        const auto gpu_large = large.project(large.add_mesh(cyl));
        // Each split really took the path it names: pieces drawn, none, fewer than all.
        EXPECT_TRUE(split.graphics_pipeline());
        EXPECT_TRUE(graphics.graphics_pipeline());
        EXPECT_FALSE(large.graphics_pipeline());
        EXPECT_GT(graphics.last_rect_count(), 0u);
        EXPECT_EQ(large.last_rect_count(), graphics.last_rect_count());
        EXPECT_EQ(compute.last_rect_count(), 0u);
        EXPECT_LT(z.last_rect_count(), graphics.last_rect_count());
        EXPECT_EQ(split.last_rect_count(), z.last_rect_count());
        const auto scan = passes::cylinder_scanline(cyl, size[0], size[1]);
        const auto cpu = passes::cylinder_raycast(cyl, size[0], size[1]);
        for (const auto& [name, image] :
             {std::pair{"zbuffer", &gpu}, std::pair{"zbuffer split through the graphics pipeline", &gpu_split},
              std::pair{"zbuffer graphics only", &gpu_graphics}, std::pair{"zbuffer compute only", &gpu_compute},
              std::pair{"zbuffer large-piece pass only", &gpu_large}, std::pair{"scanline", &scan}})
            expect_agreement(std::string(GetParam()) + " " + name, size, *image, cpu, 1e-5);
    }
}

// The float32 path devices without shaderFloat64 run: the same coverage bar; float32 keeps about
// seven digits, and where a line grazes a triangle Moller-Trumbore loses two of them, so its d
// agrees to 5e-5 rather than the double path's 1e-5 (worst measured: 1.9e-5, teapot at 540x270).
TEST_P(CylinderMeshes, ZBufferInFloatAgreesWithRaycast) {
    GIMG_REQUIRE_SHARED_MESH(path, GetParam());
    const MeshCase c = load_case(path);
    for (const Size& size : c.sizes) {
        const auto cpu = passes::cylinder_raycast(c.cyl, size[0], size[1]);
        using passes::CylinderLargePieces;
        for (const auto& [name, small, large] :
             {std::tuple{" float graphics", 0u, CylinderLargePieces::Graphics},
              std::tuple{" float compute", UINT32_MAX, CylinderLargePieces::Auto},
              std::tuple{" float large-piece pass", 0u, CylinderLargePieces::Compute}}) {
            passes::CylinderZBuffer z(ctx(), size[0], size[1],
                                      {.small_pixels = small, .large_pieces = large, .double_precision = false});
            ASSERT_FALSE(z.double_precision());
            expect_agreement(std::string(GetParam()) + name, size, z.project(z.add_mesh(c.cyl)), cpu, 5e-5);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, CylinderMeshes,
                         ::testing::Values("armadillo.off", "bunny_small.obj", "cow.off", "triceratops.off",
                                           "homer.off", "camel.off", "teapot.obj", "dragon_res4.ply"),
                         [](const ::testing::TestParamInfo<const char*>& param) {
                             std::string name = param.param;
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

// Cylindrical projection of shapes with exact answers (cylinder_analytic_cases.h), and of shapes
// checked against the literal definition (cylinder_exact.h), by every method.
#include "cylinder_analytic_cases.h"
#include "cylinder_exact.h"
#include "gpu_test.h"

#include <numbers>
#include <random>
#include <string>

using namespace gimg;

namespace {

// The z-buffer six ways: its default split between the classify pass (small pieces) and the
// large-piece pass (the device's default: compute on lavapipe), the same split with large pieces
// through the graphics pipeline (GPUs' default), every piece through the graphics pipeline, every
// piece in the classify pass, every piece in the large-piece compute pass, and the default split
// in float32 (devices without shaderFloat64).
enum class Method {
    ZBuffer,
    ZBufferSplit,
    ZBufferGraphics,
    ZBufferCompute,
    ZBufferLarge,
    ZBufferFloat,
    Raycast,
    Scanline
};

passes::CylinderZBufferOptions zbuffer_options(Method m) {
    passes::CylinderZBufferOptions o;
    if (m == Method::ZBufferSplit || m == Method::ZBufferGraphics)
        o.large_pieces = passes::CylinderLargePieces::Graphics;
    if (m == Method::ZBufferGraphics || m == Method::ZBufferLarge) o.small_pixels = 0;
    if (m == Method::ZBufferLarge) o.large_pieces = passes::CylinderLargePieces::Compute;
    if (m == Method::ZBufferCompute) o.small_pixels = UINT32_MAX;
    if (m == Method::ZBufferFloat) o.double_precision = false;
    return o;
}

std::string method_name(Method m) {
    switch (m) {
        case Method::ZBuffer:
            return "zbuffer";
        case Method::ZBufferSplit:
            return "zbuffer_split";
        case Method::ZBufferLarge:
            return "zbuffer_large";
        case Method::ZBufferGraphics:
            return "zbuffer_graphics";
        case Method::ZBufferCompute:
            return "zbuffer_compute";
        case Method::ZBufferFloat:
            return "zbuffer_float";
        case Method::Raycast:
            return "raycast";
        case Method::Scanline:
            return "scanline";
    }
    return "";
}

// Every method shares one definition, so one set of exact answers.
class CylinderAnalytic : public gimg::test::GpuTest, public ::testing::WithParamInterface<Method> {
protected:
    test::Projector projector() {
        return [this](const geo::Mesh& m, std::uint32_t w, std::uint32_t h) {
            const passes::CylinderMesh mesh = test::to_cylinder_mesh(m);
            if (GetParam() == Method::Raycast) return passes::cylinder_raycast(mesh, w, h);
            if (GetParam() == Method::Scanline) return passes::cylinder_scanline(mesh, w, h);
            passes::CylinderZBuffer z(ctx(), w, h, zbuffer_options(GetParam()));
            return z.project(z.add_mesh(mesh));
        };
    }
    double tolerance() const { return GetParam() == Method::ZBufferFloat ? 5e-5 : 2e-6; }
};

}  // namespace

TEST_P(CylinderAnalytic, SphereCentredOnTheAxis) { test::check_sphere_centred_on_the_axis(projector()); }

TEST_P(CylinderAnalytic, CubeAroundTheAxis) { test::check_cube_around_the_axis(projector(), tolerance()); }

TEST_P(CylinderAnalytic, SphereOffTheAxisIsSeenThroughTheAxisToo) { test::check_sphere_off_the_axis(projector()); }

TEST_P(CylinderAnalytic, TiltedPlateThroughTheAxisHasExceptionTrianglesAndCrossesTheSeam) {
    test::check_tilted_plate_through_the_axis(projector(), tolerance());
}

TEST_P(CylinderAnalytic, ConeDistanceIsLinearInHeight) {
    test::check_cone_distance_linear_in_height(projector(), tolerance());
}

TEST_P(CylinderAnalytic, EveryLineThroughASharedEdgeHits) {
    test::check_every_line_through_a_shared_edge(projector(), tolerance());
}

TEST_P(CylinderAnalytic, CylindricalShellAcrossTheSeam) {
    test::check_cylindrical_shell_across_the_seam(projector(), tolerance());
}

INSTANTIATE_TEST_SUITE_P(Methods, CylinderAnalytic,
                         ::testing::Values(Method::ZBuffer, Method::ZBufferSplit, Method::ZBufferGraphics,
                                           Method::ZBufferCompute, Method::ZBufferLarge, Method::ZBufferFloat,
                                           Method::Raycast, Method::Scanline),
                         [](const ::testing::TestParamInfo<Method>& p) { return method_name(p.param); });

// Where there is no closed form: the definition evaluated literally (cylinder_exact.h).
namespace {

class CylinderDefinition : public gimg::test::GpuTest, public ::testing::WithParamInterface<Method> {
protected:
    passes::CylinderImage project(const passes::CylinderMesh& mesh, std::uint32_t w, std::uint32_t h,
                                  const passes::CylinderTransform& t = passes::kIdentityTransform) {
        if (GetParam() == Method::Raycast) return passes::cylinder_raycast(mesh, w, h, t);
        passes::CylinderZBuffer z(ctx(), w, h, zbuffer_options(GetParam()));
        return z.project(z.add_mesh(mesh), t);
    }
};

glm::dvec3 at(double r, double degrees, double y) {
    const double a = degrees * std::numbers::pi / 180.0;
    return {r * std::cos(a), y, r * std::sin(a)};
}

}  // namespace

TEST_P(CylinderDefinition, TriangleFarFromTheAxisCoversExactlyThePixelsOfTheDefinition) {
    // Spanning 100 degrees at radius ~0.85: its edges bow visibly in (theta, y). Wound both ways:
    // seen directly (d > 0) and, facing the axis, seen through it half a turn away (d < 0).
    const glm::dvec3 p0 = at(0.85, -40.0, 0.1), p1 = at(0.9, 10.0, 0.95), p2 = at(0.8, 60.0, 0.3);
    for (const bool through_the_axis : {false, true}) {
        const passes::CylinderMesh mesh =
            test::soup(through_the_axis ? std::vector{p0, p2, p1} : std::vector{p0, p1, p2});
        const std::uint32_t W = 720, H = 360;
        const test::Agreement a = test::compare(project(mesh, W, H), test::brute_force(mesh, W, H));
        EXPECT_GT(a.covered, 10000u);
        EXPECT_EQ(a.coverage_differs, 0u);
        EXPECT_EQ(a.depth_differs, 0u) << "max |delta d| " << a.max_depth_error;
    }
}

TEST_P(CylinderDefinition, RandomTriangleSoupThroughATransformMatchesTheDefinition) {
    // Triangles of all sizes across the axis (exception triangles), across the seam, facing the
    // axis, poking out of the wall; through a transform.
    std::mt19937 rng(1977);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<glm::dvec3> corners;
    for (int k = 0; k < 300; ++k) {
        const double r = 0.95 * unit(rng), a = 2.0 * std::numbers::pi * unit(rng);
        const glm::dvec3 centre{r * std::cos(a), unit(rng), r * std::sin(a)};
        const double size = k % 10 == 0 ? 0.8 : 0.05 + 0.35 * unit(rng);
        for (int c = 0; c < 3; ++c)
            corners.push_back(centre + size * glm::dvec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5));
    }
    const passes::CylinderTransform m{0, 0, -0.9f, 0, 0, 0.9f, 0, 0.05f, 0.9f, 0, 0, 0};
    const passes::CylinderMesh mesh = test::soup(corners);
    const std::uint32_t W = 360, H = 180;
    const test::Agreement a = test::compare(project(mesh, W, H, m), test::brute_force(mesh, W, H, m));
    EXPECT_GT(a.covered, W * H / 2);
    EXPECT_LE(a.coverage_differs, W * H / 2000) << "more than 0.05 % of the pixels";
    EXPECT_LE(a.depth_differs, W * H / 2000) << "max |delta d| " << a.max_depth_error;
}

INSTANTIATE_TEST_SUITE_P(Methods, CylinderDefinition,
                         ::testing::Values(Method::ZBuffer, Method::ZBufferSplit, Method::ZBufferGraphics,
                                           Method::ZBufferCompute, Method::ZBufferLarge, Method::ZBufferFloat,
                                           Method::Raycast),
                         [](const ::testing::TestParamInfo<Method>& p) { return method_name(p.param); });

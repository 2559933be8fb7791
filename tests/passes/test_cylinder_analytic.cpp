// Cylindrical projection of shapes with exact answers (cylinder_analytic_cases.h), by the GPU
// Z-buffer and by the CPU ray caster (the scanline method has its own file).
#include "cylinder_analytic_cases.h"
#include "gpu_test.h"

using namespace gimg;

namespace {

class CylinderAnalytic : public gimg::test::GpuTest {
protected:
    test::Projector zbuffer() {
        return [this](const geo::Mesh& m, std::uint32_t w, std::uint32_t h) {
            passes::CylinderZBuffer z(ctx(), w, h);
            return z.project(z.add_mesh(test::to_cylinder_mesh(m)));
        };
    }
};

}  // namespace

TEST_F(CylinderAnalytic, SphereCentredOnTheAxis) { test::check_sphere_centred_on_the_axis(zbuffer()); }

TEST_F(CylinderAnalytic, CubeAroundTheAxis) { test::check_cube_around_the_axis(zbuffer()); }

TEST_F(CylinderAnalytic, SphereOffTheAxisIsSeenThroughTheAxisToo) { test::check_sphere_off_the_axis(zbuffer()); }

TEST_F(CylinderAnalytic, TiltedPlateThroughTheAxisHasExceptionTrianglesAndCrossesTheSeam) {
    test::check_tilted_plate_through_the_axis(zbuffer());
}

TEST_F(CylinderAnalytic, ConeDistanceIsLinearInHeight) { test::check_cone_distance_linear_in_height(zbuffer()); }

TEST_F(CylinderAnalytic, CylindricalShellAcrossTheSeam) { test::check_cylindrical_shell_across_the_seam(zbuffer()); }

namespace {
const test::Projector kRaycast = [](const geo::Mesh& m, std::uint32_t w, std::uint32_t h) {
    return passes::cylinder_raycast(test::to_cylinder_mesh(m), w, h);
};
}  // namespace

TEST(CylinderAnalyticRaycast, SphereCentredOnTheAxis) { test::check_sphere_centred_on_the_axis(kRaycast); }
TEST(CylinderAnalyticRaycast, CubeAroundTheAxis) { test::check_cube_around_the_axis(kRaycast); }
TEST(CylinderAnalyticRaycast, SphereOffTheAxisIsSeenThroughTheAxisToo) { test::check_sphere_off_the_axis(kRaycast); }
TEST(CylinderAnalyticRaycast, TiltedPlateThroughTheAxisHasExceptionTrianglesAndCrossesTheSeam) {
    test::check_tilted_plate_through_the_axis(kRaycast);
}
TEST(CylinderAnalyticRaycast, ConeDistanceIsLinearInHeight) { test::check_cone_distance_linear_in_height(kRaycast); }
TEST(CylinderAnalyticRaycast, CylindricalShellAcrossTheSeam) { test::check_cylindrical_shell_across_the_seam(kRaycast); }

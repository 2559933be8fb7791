// The mesh renderer: analytic coverage of a sphere, determinism, options that must change the
// picture, bad input, and a golden image on top.
#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/render.h"

#include "gpu_test.h"
#include "image_expect.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>

using namespace gimg;

namespace {
class Render : public gimg::test::GpuTest {};

std::size_t covered_pixels(const geo::RgbaImage& img) {
    std::size_t n = 0;
    for (std::size_t p = 0; p < img.pixels.size() / 4; ++p) n += img.pixels[4 * p + 3] >= 128;
    return n;
}

std::size_t dark_pixels(const geo::RgbaImage& img) {
    std::size_t n = 0;
    for (std::size_t p = 0; p < img.pixels.size() / 4; ++p) n += img.pixels[4 * p] < 80;
    return n;
}
}  // namespace

TEST_F(Render, UnitSphereCoversTheAnalyticDisc) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 6);
    passes::RenderOptions o;
    o.width = 640;
    o.height = 480;
    const passes::Camera camera = passes::fit_camera(sphere.positions, o.view, 640.0 / 480.0);
    const geo::RgbaImage img = passes::render_mesh(ctx(), sphere, o, camera);
    // A sphere seen from distance D subtends asin(1/D); its image is a disc of that angular radius.
    const double distance = glm::length(camera.eye - camera.target);
    const double radius_px =
        std::tan(std::asin(1.0 / distance)) / std::tan(0.5 * glm::radians(camera.fov_y_deg)) * 240.0;
    const double expected = std::numbers::pi * radius_px * radius_px;
    const double actual = double(covered_pixels(img));
    EXPECT_NEAR(actual, expected, 0.01 * expected) << "disc radius " << radius_px << " px";
    std::printf("sphere coverage: %.0f pixels, analytic disc %.1f (ratio %.5f)\n", actual, expected, actual / expected);
    EXPECT_GT(radius_px, 150.0);  // the fit fills the frame
}

TEST_F(Render, SameInputSamePicture) {
    const geo::Mesh torus = geo::make_torus(2.0, 0.6, 40, 20);
    passes::RenderOptions o;
    o.width = 200;
    o.height = 150;
    o.wireframe = true;
    const geo::RgbaImage a = passes::render_mesh(ctx(), torus, o);
    const geo::RgbaImage b = passes::render_mesh(ctx(), torus, o);
    EXPECT_EQ(a.pixels, b.pixels);
}

TEST_F(Render, WireframeAndColourModesChangeWhatTheyShould) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 2);
    passes::RenderOptions o;
    o.width = 256;
    o.height = 256;
    const geo::RgbaImage plain = passes::render_mesh(ctx(), sphere, o);
    o.wireframe = true;
    const geo::RgbaImage wire = passes::render_mesh(ctx(), sphere, o);
    EXPECT_GT(dark_pixels(wire), dark_pixels(plain) + 1000);  // 320 faces' edges are visible
    EXPECT_EQ(covered_pixels(wire), covered_pixels(plain));   // the silhouette is the same

    o.wireframe = false;
    o.color = passes::MeshColor::Scalar;
    o.scalars.resize(sphere.vertex_count());
    for (std::size_t i = 0; i < sphere.vertex_count(); ++i) o.scalars[i] = float(sphere.positions[i].y);
    const geo::RgbaImage scalar = passes::render_mesh(ctx(), sphere, o);
    // Viridis: the top (y = 1) is yellow (red > blue), the bottom purple (blue > red).
    const std::uint8_t* top = scalar.at(128, 70);
    const std::uint8_t* bottom = scalar.at(128, 186);
    EXPECT_GT(top[0], top[2]);
    EXPECT_GT(bottom[2], bottom[0]);

    o.scalars.pop_back();
    EXPECT_THROW(passes::render_mesh(ctx(), sphere, o), geo::InputError);
    EXPECT_THROW(passes::render_mesh(ctx(), geo::Mesh{}, passes::RenderOptions{}), geo::InputError);
}

TEST_F(Render, SideBySideUsesOneCameraForBoth) {
    const geo::Mesh a = geo::make_icosphere(1.0, 3);
    passes::RenderOptions o;
    o.width = 200;
    o.height = 200;
    const geo::RgbaImage pair = passes::render_side_by_side(ctx(), a, a, o);
    ASSERT_EQ(pair.width, 400u);
    // The same mesh under the same camera: the halves are identical.
    for (std::uint32_t y = 0; y < 200; ++y)
        for (std::uint32_t x = 0; x < 200; ++x)
            for (int c = 0; c < 4; ++c) ASSERT_EQ(pair.at(x, y)[c], pair.at(x + 200, y)[c]);
}

TEST_F(Render, GoldenTorus) {
    if (!ctx().device_info().is_lavapipe) GTEST_SKIP() << "the golden image was made on lavapipe";
    passes::RenderOptions o;
    o.width = 320;
    o.height = 240;
    o.wireframe = true;
    o.color = passes::MeshColor::Normal;
    const geo::RgbaImage img = passes::render_mesh(ctx(), geo::make_torus(2.0, 0.7, 36, 18), o);
    EXPECT_TRUE(gimg::test::matches_golden(img, "render_torus_normals_wire.png", 8, 0.005));
}

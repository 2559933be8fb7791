// A graphics pass drawing a known triangle offscreen covers exactly the pixels whose centres lie
// inside it, computed here in exact integer arithmetic.
#include "gimg/engine/graph.h"

#include "gpu_test.h"

#include "engine/pixel_triangle_vert.h"
#include "engine/solid_frag.h"

#include <array>
#include <cstdint>

using namespace gimg;

class RasterPass : public gimg::test::GpuTest {};

namespace {

const RasterProgram kSolidTriangle{GIMG_SPIRV(gimg_spv_engine_pixel_triangle_vert),
                                   GIMG_SPIRV(gimg_spv_engine_solid_frag),
                                   RasterState{.depth_test = false, .depth_write = false}};

// Vertices on the 1/16-pixel grid, which every Vulkan rasteriser represents exactly
// (subPixelPrecisionBits >= 4), so the expected coverage is exact.
constexpr std::int64_t kSub = 16;
const std::array<std::array<std::int64_t, 2>, 3> kTriangle{
    {{3 * kSub + 5, 4 * kSub + 11}, {60 * kSub + 3, 12 * kSub + 13}, {21 * kSub + 9, 58 * kSub + 15}}};

std::int64_t edge(const std::array<std::int64_t, 2>& a, const std::array<std::int64_t, 2>& b, std::int64_t px,
                  std::int64_t py) {
    return (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
}

}  // namespace

TEST_F(RasterPass, RasterPassCoversExactlyThePixelCentresInsideTheTriangle) {
    constexpr std::uint32_t W = 64, H = 64;
    Image target = ctx().create_image({W, H, Format::RGBA8, "target"});
    std::array<float, 6> positions{};
    for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 2; ++k) positions[2 * v + k] = float(kTriangle[v][k]) / float(kSub);
    Buffer vertices = ctx().create_buffer({sizeof(positions), "vertices"});
    ctx().upload(vertices, positions.data(), sizeof(positions));

    Graph g(ctx());
    auto img = g.import_image(target);
    auto verts = g.import_buffer(vertices);
    const std::array<float, 2> extent{float(W), float(H)};
    g.add_raster_pass(
        "triangle",
        [&](PassBuilder& b) {
            b.read(verts, Access::VertexRead);
            img = b.color(img, ClearValue::color(0, 0, 0, 0));
        },
        [=](Cmd& c) { c.draw(kSolidTriangle, 3, 1, {verts}, extent); });
    g.export_image(img, Access::TransferSrc);
    g.compile().execute();
    std::vector<std::byte> pixels = ctx().download(target);

    std::size_t covered = 0, mismatches = 0;
    for (std::uint32_t y = 0; y < H; ++y) {
        for (std::uint32_t x = 0; x < W; ++x) {
            const std::int64_t px = std::int64_t(x) * kSub + kSub / 2, py = std::int64_t(y) * kSub + kSub / 2;
            const std::int64_t e0 = edge(kTriangle[0], kTriangle[1], px, py);
            const std::int64_t e1 = edge(kTriangle[1], kTriangle[2], px, py);
            const std::int64_t e2 = edge(kTriangle[2], kTriangle[0], px, py);
            ASSERT_TRUE(e0 && e1 && e2) << "test set-up: a pixel centre lies on an edge";
            const bool inside = (e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0);
            const std::byte* p = &pixels[(std::size_t(y) * W + x) * 4];
            const bool drawn = p[3] == std::byte{255} && p[0] == std::byte{255};
            const bool empty =
                p[0] == std::byte{0} && p[1] == std::byte{0} && p[2] == std::byte{0} && p[3] == std::byte{0};
            covered += inside;
            mismatches += inside ? !drawn : !empty;
        }
    }
    EXPECT_EQ(mismatches, 0u) << "of " << covered << " covered pixels";
    EXPECT_GT(covered, 1000u);  // the triangle is big enough to mean something
}

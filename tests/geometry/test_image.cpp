#include "gimg/geometry/error.h"
#include "gimg/geometry/image.h"

#include "test_data.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

using namespace gimg::geo;

TEST(Image, PngRoundTripIsLossless) {
    RgbaImage img(17, 9);
    for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = std::uint8_t(i * 37 % 256);
    auto path = gimg::test::output_dir("image") / "roundtrip.png";
    write_png(img, path);
    RgbaImage back = read_png(path);
    EXPECT_EQ(back.width, 17u);
    EXPECT_EQ(back.height, 9u);
    EXPECT_EQ(back.pixels, img.pixels);
}

TEST(Image, CompareCountsPixelsBeyondTheTolerance) {
    RgbaImage a(10, 10), b(10, 10);
    b.at(3, 4)[0] = 10;   // within a tolerance of 10
    b.at(5, 5)[2] = 200;  // beyond
    b.at(9, 9)[3] = 11;   // beyond
    ImageDifference d = compare_images(a, b, 10);
    EXPECT_TRUE(d.same_size);
    EXPECT_EQ(d.max_abs_difference, 200);
    EXPECT_EQ(d.differing_pixels, 2u);
    EXPECT_DOUBLE_EQ(d.differing_share, 0.02);
    EXPECT_GT(d.diff.at(5, 5)[0], 200);
    EXPECT_EQ(compare_images(a, RgbaImage(10, 11), 0).differing_share, 1.0);
}

TEST(Image, UnreadableFilesAreInputErrors) {
    auto path = gimg::test::output_dir("image") / "not_a.png";
    std::ofstream(path) << "garbage";
    EXPECT_THROW(read_png(path), InputError);
    EXPECT_THROW(read_png(gimg::test::output_dir("image") / "missing.png"), InputError);
    EXPECT_THROW(write_png(RgbaImage(2, 2), "/nonexistent-folder/x.png"), InputError);
}

#include "gimg/geometry/exr.h"

TEST(Exr, FloatChannelsRoundTripBitExactly) {
    FloatImage img;
    img.width = 7;
    img.height = 5;
    auto& d = img.channels["d"];
    auto& mask = img.channels["mask"];
    for (int i = 0; i < 35; ++i) {
        d.push_back(0.1f * float(i) - 1.0f + 1e-7f * float(i));
        mask.push_back(i % 3 == 0 ? 0.0f : 1.0f);
    }
    auto path = gimg::test::output_dir("image") / "roundtrip.exr";
    write_exr(img, path);
    FloatImage back = read_exr(path);
    EXPECT_EQ(back.width, 7u);
    EXPECT_EQ(back.height, 5u);
    EXPECT_EQ(back.channels.at("d"), d);
    EXPECT_EQ(back.channels.at("mask"), mask);
    auto bad = gimg::test::output_dir("image") / "bad.exr";
    std::ofstream(bad) << "not an exr";
    EXPECT_THROW(read_exr(bad), InputError);
    EXPECT_THROW(read_exr(gimg::test::output_dir("image") / "missing.exr"), InputError);
    try {  // a folder is named as one, not as missing
        read_exr(gimg::test::output_dir("image"));
        ADD_FAILURE() << "a folder was read as an image";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("is a folder, not an image"), std::string::npos) << e.what();
    }
}

// A header claiming more than its file holds is refused by name before anything that large is made:
// OpenEXR's line buffers past 65,536 columns (the fuzzer's 392-byte file claiming 16.7 million asked
// for 2.2 GB), gimg's channels past what the bytes can hold.
TEST(Exr, AHeaderClaimingMoreThanItsFileHoldsIsRefused) {
    FloatImage img;
    img.width = 7;
    img.height = 5;
    img.channels["d"].assign(35, 0.5f);
    const auto path = gimg::test::output_dir("image") / "claims.exr";
    write_exr(img, path);
    std::ifstream in(path, std::ios::binary);
    const std::string original((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Both windows' box2i (min x, min y, max x, max y, little-endian) made to claim max_x x max_y.
    // `padding` zero bytes appended, so that OpenEXR finds a whole table of line offsets.
    auto claiming = [&](std::int32_t max_x, std::int32_t max_y, std::size_t padding = 0) {
        std::string bytes = original + std::string(padding, '\0');
        for (const char* window : {"dataWindow", "displayWindow"}) {
            const std::string key = std::string(window) + '\0' + "box2i" + '\0';
            const std::size_t at = bytes.find(key);
            EXPECT_NE(at, std::string::npos) << window;
            if (at == std::string::npos) continue;
            const std::int32_t box[4] = {0, 0, max_x, max_y};
            std::memcpy(&bytes[at + key.size() + 4], box, sizeof box);  // after the attribute's size
        }
        const auto out = gimg::test::output_dir("image") / "claims_patched.exr";
        std::ofstream(out, std::ios::binary) << bytes;
        try {
            read_exr(out);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("read");
    };
    EXPECT_EQ(claiming(6, 4), "read");  // the patch itself leaves a good file good
    EXPECT_NE(claiming(0x00ffff1f, 4).find("exceeds the maximum width"), std::string::npos) << claiming(0x00ffff1f, 4);
    // 65,536 x 2,048 floats (512 MB) in 2 KB: OpenEXR opens it, gimg refuses before allocating.
    const std::string big = claiming(65535, 2047, 2048);
    EXPECT_NE(big.find("claims 65536 x 2048 pixels of 1 channel, more than its"), std::string::npos) << big;
}

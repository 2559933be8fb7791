#include "gimg/geometry/error.h"
#include "gimg/geometry/image.h"

#include "test_data.h"

#include <gtest/gtest.h>

#include <fstream>
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

#pragma once
// 8-bit RGBA pictures on the CPU: PNG in and out (stb), and the image comparison every image test
// uses (max absolute channel difference, share of differing pixels, a diff picture).

#include <cstdint>
#include <filesystem>
#include <vector>

namespace gimg::geo {

struct RgbaImage {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::vector<std::uint8_t> pixels;  // row-major from the top row, 4 bytes per pixel

    RgbaImage() = default;
    RgbaImage(std::uint32_t w, std::uint32_t h) : width(w), height(h), pixels(std::size_t(w) * h * 4, 0) {}
    std::uint8_t* at(std::uint32_t x, std::uint32_t y) { return &pixels[(std::size_t(y) * width + x) * 4]; }
    const std::uint8_t* at(std::uint32_t x, std::uint32_t y) const { return &pixels[(std::size_t(y) * width + x) * 4]; }
};

// Writes atomically (temporary file, then rename). Throws InputError naming the path.
void write_png(const RgbaImage& image, const std::filesystem::path& path);
// Throws InputError for a missing or undecodable file.
RgbaImage read_png(const std::filesystem::path& path);

struct ImageDifference {
    bool same_size = false;
    int max_abs_difference = 0;        // largest |a - b| over all channels of all pixels
    std::size_t differing_pixels = 0;  // pixels with some channel differing by more than the tolerance
    double differing_share = 0.0;      // differing_pixels / pixel count
    RgbaImage diff;                    // black where equal, red scaled by the difference elsewhere
};

// Pixels differ when any channel differs by more than `channel_tolerance`.
ImageDifference compare_images(const RgbaImage& a, const RgbaImage& b, int channel_tolerance);

}  // namespace gimg::geo

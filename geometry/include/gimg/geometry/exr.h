#pragma once
// Lossless float32 images in OpenEXR: geometry images (channel "d" for cylindrical distance,
// "R", "G", "B" for positions of parameterization images) with a validity channel ("mask" or "A").

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace gimg::geo {

struct FloatImage {
    std::uint32_t width = 0, height = 0;
    // Named channels, each width * height floats, row-major from the top row.
    std::map<std::string, std::vector<float>> channels;
};

// Writes float32 channels (ZIP compression, lossless) atomically: a temporary file, then rename.
// Throws InputError naming the path on failure.
void write_exr(const FloatImage& image, const std::filesystem::path& path);
// Reads every channel as float32. Throws InputError for a missing, truncated or non-EXR file.
FloatImage read_exr(const std::filesystem::path& path);

}  // namespace gimg::geo

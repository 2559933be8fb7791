#include "gimg/geometry/image.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cstdlib>
#include <string>

namespace gimg::geo {

void write_png(const RgbaImage& image, const std::filesystem::path& path) {
    if (image.width == 0 || image.height == 0 || image.pixels.size() != std::size_t(image.width) * image.height * 4)
        throw InputError("cannot write " + path.string() + ": empty or malformed image");
    std::string encoded;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
    };
    if (!stbi_write_png_to_func(append, &encoded, int(image.width), int(image.height), 4, image.pixels.data(),
                                int(image.width * 4)))
        throw InputError("cannot encode " + path.string() + " as PNG");
    write_file_atomically(path, encoded);
}

RgbaImage read_png(const std::filesystem::path& path) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
    if (!data) throw InputError("cannot read image " + path.string() + ": " + stbi_failure_reason());
    RgbaImage image{static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h)};
    std::copy(data, data + std::size_t(w) * h * 4, image.pixels.begin());
    stbi_image_free(data);
    return image;
}

ImageDifference compare_images(const RgbaImage& a, const RgbaImage& b, int channel_tolerance) {
    ImageDifference d;
    d.same_size = a.width == b.width && a.height == b.height && a.pixels.size() == b.pixels.size();
    if (!d.same_size) {
        d.max_abs_difference = 255;
        d.differing_pixels = std::max<std::size_t>(a.pixels.size(), b.pixels.size()) / 4;
        d.differing_share = 1.0;
        return d;
    }
    d.diff = RgbaImage(a.width, a.height);
    for (std::size_t p = 0; p < a.pixels.size() / 4; ++p) {
        int worst = 0;
        for (int c = 0; c < 4; ++c)
            worst = std::max(worst, std::abs(int(a.pixels[4 * p + c]) - int(b.pixels[4 * p + c])));
        d.max_abs_difference = std::max(d.max_abs_difference, worst);
        std::uint8_t* out = &d.diff.pixels[4 * p];
        out[3] = 255;
        if (worst > channel_tolerance) {
            ++d.differing_pixels;
            out[0] = std::uint8_t(std::min(255, 64 + worst));
        } else {
            // Faint grey copy of the first image, so the diff shows where things are.
            out[0] = out[1] = out[2] = std::uint8_t(a.pixels[4 * p + 1] / 4);
        }
    }
    d.differing_share = a.pixels.empty() ? 0.0 : double(d.differing_pixels) / double(a.pixels.size() / 4);
    return d;
}

}  // namespace gimg::geo

// Parameterization geometry images in EXR: R, G, B = x, y, z and A = 1 covered / 0 empty.
#include "gimg/passes/reconstruct.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"

#include <cmath>

namespace gimg::passes {

void write_position_exr(const PositionImage& image, const std::filesystem::path& path) {
    geo::FloatImage exr;
    exr.width = image.width;
    exr.height = image.height;
    const std::size_t n = image.covered.size();
    auto& r = exr.channels["R"];
    auto& g = exr.channels["G"];
    auto& b = exr.channels["B"];
    auto& a = exr.channels["A"];
    r.resize(n), g.resize(n), b.resize(n), a.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const bool c = image.covered[i];
        r[i] = c ? image.xyz[3 * i] : 0.0f;
        g[i] = c ? image.xyz[3 * i + 1] : 0.0f;
        b[i] = c ? image.xyz[3 * i + 2] : 0.0f;
        a[i] = c ? 1.0f : 0.0f;
    }
    geo::write_exr(exr, path);
}

PositionImage read_position_exr(const std::filesystem::path& path) {
    const geo::FloatImage exr = geo::read_exr(path);
    for (const char* c : {"R", "G", "B"})
        if (!exr.channels.count(c))
            throw geo::InputError(path.string() + " has no channel " + c + ": not a position geometry image");
    auto mask = exr.channels.find("A");
    PositionImage image(exr.width, exr.height);
    const auto &r = exr.channels.at("R"), &g = exr.channels.at("G"), &b = exr.channels.at("B");
    for (std::size_t i = 0; i < image.covered.size(); ++i) {
        const bool covered = mask != exr.channels.end() ? mask->second[i] > 0.5f : true;
        if (covered && !(std::isfinite(r[i]) && std::isfinite(g[i]) && std::isfinite(b[i])))
            throw geo::InputError(path.string() + ": pixel " + std::to_string(i) + " holds a NaN or infinite position");
        image.covered[i] = covered;
        if (covered) image.xyz[3 * i] = r[i], image.xyz[3 * i + 1] = g[i], image.xyz[3 * i + 2] = b[i];
    }
    return image;
}

}  // namespace gimg::passes

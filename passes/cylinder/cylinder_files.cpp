// The files a cylindrical geometry image lives in: distance.exr, distance.png and frame.json.
#include "gimg/passes/cylinder.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace gimg::passes {

geo::RgbaImage cylinder_preview(const CylinderImage& image) {
    geo::RgbaImage out(image.width, image.height);
    // Brightness is |d| relative to the image's largest |d|, so every model uses the full range.
    float largest = 0.0f;
    for (std::size_t i = 0; i < image.covered.size(); ++i)
        if (image.covered[i]) largest = std::max(largest, std::abs(image.distance[i]));
    for (std::size_t i = 0; i < image.covered.size(); ++i) {
        std::uint8_t* p = &out.pixels[4 * i];
        p[3] = 255;
        if (!image.covered[i]) continue;
        const float d = image.distance[i];
        // A little light even at d = 0, so covered pixels never read as empty.
        const float b = 0.15f + 0.85f * (largest > 0.0f ? std::abs(d) / largest : 0.0f);
        const float warm[3] = {1.0f, 0.86f, 0.62f}, cold[3] = {0.50f, 0.76f, 1.0f};
        const float* hue = d >= 0.0f ? warm : cold;
        for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(std::lround(255.0f * b * hue[c]));
    }
    return out;
}

void write_cylinder_files(const std::filesystem::path& dir, const CylinderImage& image, const CylinderFrame& frame,
                          const CylinderFileInfo& info) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw geo::InputError("cannot create folder " + dir.string() + ": " + ec.message());

    geo::FloatImage exr;
    exr.width = image.width;
    exr.height = image.height;
    auto& d = exr.channels["d"];
    auto& mask = exr.channels["mask"];
    d.resize(image.distance.size());
    mask.resize(image.distance.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
        d[i] = image.covered[i] ? image.distance[i] : 0.0f;
        mask[i] = image.covered[i] ? 1.0f : 0.0f;
    }
    geo::write_exr(exr, dir / "distance.exr");
    geo::write_png(cylinder_preview(image), dir / "distance.png");

    nlohmann::json j;
    j["rotation"] = nlohmann::json::array();
    for (int r = 0; r < 3; ++r)
        j["rotation"].push_back({frame.rotation[0][r], frame.rotation[1][r], frame.rotation[2][r]});
    j["translation"] = {frame.translation.x, frame.translation.y, frame.translation.z};
    j["scale"] = frame.scale;
    j["to_cylinder"] = "p_cylinder = scale * rotation * p + translation (rotation as rows)";
    j["image"] = {{"width", image.width},    {"height", image.height}, {"theta", "2*pi*(u+0.5)/width"},
                  {"y", "1-(v+0.5)/height"}, {"row_0", "top"},         {"point", "(d*cos(theta), y, d*sin(theta))"},
                  {"empty", "mask == 0"}};
    j["source"] = info.source;
    j["method"] = info.method;
    geo::write_file_atomically(dir / "frame.json", j.dump(2) + "\n");
}

CylinderImage read_cylinder_exr(const std::filesystem::path& path) {
    const geo::FloatImage exr = geo::read_exr(path);
    auto d = exr.channels.find("d");
    if (d == exr.channels.end())
        throw geo::InputError(path.string() + " has no channel \"d\": not a cylindrical geometry image");
    auto mask = exr.channels.find("mask");
    CylinderImage image(exr.width, exr.height);
    for (std::size_t i = 0; i < image.distance.size(); ++i) {
        const float v = d->second[i];
        const bool covered = mask != exr.channels.end() ? mask->second[i] > 0.5f : std::isfinite(v);
        if (covered && !(std::abs(v) <= 1.0f))
            throw geo::InputError(path.string() + ": d = " + std::to_string(v) + " outside [-1, 1] at pixel " +
                                  std::to_string(i));
        image.covered[i] = covered;
        image.distance[i] = covered ? v : 0.0f;
    }
    return image;
}

CylinderFrame read_cylinder_frame(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw geo::InputError("cannot read " + path.string());
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        CylinderFrame f;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) f.rotation[c][r] = j.at("rotation").at(r).at(c).get<double>();
        for (int k = 0; k < 3; ++k) f.translation[k] = j.at("translation").at(k).get<double>();
        f.scale = j.at("scale").get<double>();
        if (!(f.scale > 0.0) || !std::isfinite(f.scale))
            throw geo::InputError(path.string() + ": scale must be positive");
        return f;
    } catch (const nlohmann::json::exception& e) {
        throw geo::InputError(path.string() + " is not a gimg frame.json: " + e.what());
    }
}

}  // namespace gimg::passes

// The files a cylindrical geometry image lives in: distance.exr, distance.png and frame.json.
#include "gimg/passes/cylinder.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

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

namespace {

// FNV-1a over the image's size, mask and covered distances: frame.json records it, so a reader can
// tell an image from another run (an interrupted or concurrent one) beside it.
std::string image_stamp(const CylinderImage& image) {
    std::uint64_t h = 14695981039346656037ull;
    auto mix = [&](const void* data, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
    };
    mix(&image.width, 4);
    mix(&image.height, 4);
    for (std::size_t i = 0; i < image.covered.size(); ++i) {
        mix(&image.covered[i], 1);
        if (image.covered[i]) mix(&image.distance[i], 4);
    }
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
    return text;
}

}  // namespace

void write_cylinder_files(const std::filesystem::path& dir, const CylinderImage& image, const CylinderFrame& frame,
                          const CylinderFileInfo& info) {
    std::error_code ec;
    if (std::filesystem::exists(dir, ec))  // refuse before writing any of the three
        for (const char* name : {"distance.exr", "distance.png", "frame.json"}) geo::check_output_target(dir / name);
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
    geo::OutputSet files;  // the three files appear together, frame.json (the stamp) last
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
    j["image_stamp"] = image_stamp(image);
    geo::write_file_atomically(dir / "frame.json", j.dump(2) + "\n");
    files.commit();
}

CylinderImage read_cylinder_exr(const std::filesystem::path& path) {
    const geo::FloatImage exr = geo::read_exr(path);
    auto d = exr.channels.find("d");
    if (d == exr.channels.end())
        throw geo::InputError(path.string() + " has no channel \"d\": not a cylindrical geometry image");
    auto mask = exr.channels.find("mask");
    if (mask == exr.channels.end())
        throw geo::InputError(path.string() +
                              " has no channel \"mask\" (1 covered, 0 empty): not a gimg cylindrical image");
    CylinderImage image(exr.width, exr.height);
    for (std::size_t i = 0; i < image.distance.size(); ++i) {
        const float v = d->second[i], m = mask->second[i];
        if (m != 0.0f && m != 1.0f)
            throw geo::InputError(path.string() + ": mask = " + std::to_string(m) + " at pixel " + std::to_string(i) +
                                  " (it must be 0 or 1)");
        const bool covered = m == 1.0f;
        if (covered && !(std::abs(v) <= 1.0f))
            throw geo::InputError(path.string() + ": d = " + std::to_string(v) + " outside [-1, 1] at pixel " +
                                  std::to_string(i));
        image.covered[i] = covered;
        image.distance[i] = covered ? v : 0.0f;
    }
    return image;
}

namespace {

nlohmann::json read_frame_json(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw geo::InputError(path.string() + " is a folder, not a frame.json");
    std::ifstream in(path);
    if (!in)
        throw geo::InputError("cannot read " + path.string() + ": no such file (it is written beside distance.exr)");
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw geo::InputError(path.string() + " is not a gimg frame.json: " + e.what());
    }
}

CylinderFrame frame_of(const nlohmann::json& j, const std::filesystem::path& path) {
    CylinderFrame f;
    try {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) f.rotation[c][r] = j.at("rotation").at(r).at(c).get<double>();
        for (int k = 0; k < 3; ++k) f.translation[k] = j.at("translation").at(k).get<double>();
        f.scale = j.at("scale").get<double>();
    } catch (const nlohmann::json::exception& e) {
        throw geo::InputError(path.string() + " is not a gimg frame.json: " + e.what());
    }
    if (!(f.scale > 0.0) || !std::isfinite(f.scale)) throw geo::InputError(path.string() + ": scale must be positive");
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(f.translation[k])) throw geo::InputError(path.string() + ": translation is not finite");
    // A rotation: orthonormal rows (to the precision a dump of doubles keeps) and no mirror.
    const glm::dmat3 should_be_identity = glm::transpose(f.rotation) * f.rotation;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            if (!(std::abs(should_be_identity[c][r] - (r == c ? 1.0 : 0.0)) <= 1e-9))
                throw geo::InputError(path.string() + ": rotation is not a rotation (its rows are not orthonormal)");
    if (!(glm::determinant(f.rotation) > 0.0)) throw geo::InputError(path.string() + ": rotation is a mirror");
    return f;
}

}  // namespace

CylinderFrame read_cylinder_frame(const std::filesystem::path& path) { return frame_of(read_frame_json(path), path); }

CylinderFiles read_cylinder_files(const std::filesystem::path& exr_path) {
    const std::filesystem::path frame_path = exr_path.parent_path() / "frame.json";
    const nlohmann::json j = read_frame_json(frame_path);
    CylinderFiles files{read_cylinder_exr(exr_path), frame_of(j, frame_path)};
    if (j.contains("image")) {
        const auto& layout = j["image"];
        if (layout.value("width", 0u) != files.image.width || layout.value("height", 0u) != files.image.height)
            throw geo::InputError(frame_path.string() + " describes a " + std::to_string(layout.value("width", 0u)) +
                                  "x" + std::to_string(layout.value("height", 0u)) + " image, " + exr_path.string() +
                                  " is " + std::to_string(files.image.width) + "x" +
                                  std::to_string(files.image.height) +
                                  ": they come from different runs; run gimg cylinder again");
    }
    if (j.contains("image_stamp") && j["image_stamp"] != image_stamp(files.image))
        throw geo::InputError(exr_path.string() + " is not the image " + frame_path.string() +
                              " was written with (an interrupted or concurrent run?); run gimg cylinder again");
    return files;
}

}  // namespace gimg::passes

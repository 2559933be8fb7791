// The files a cylindrical geometry image lives in: distance.exr, distance.png and frame.json.
#include "gimg/passes/cylinder.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"

#include "frame_json.h"

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

std::string image_stamp(const CylinderImage& image) {
    return detail::stamp_of(image.width, image.height, image.covered, image.distance);
}

}  // namespace

void write_cylinder_files(const std::filesystem::path& dir, const CylinderImage& image, const CylinderFrame& frame,
                          const CylinderFileInfo& info) {
    std::error_code ec;
    if (std::filesystem::exists(dir, ec))  // refuse before writing any of the three
        for (const char* name : {"distance.exr", "distance.png", "frame.json"}) geo::check_output_target(dir / name);
    ec = geo::create_output_folder(dir);
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

    nlohmann::json j = detail::frame_json(frame);
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

CylinderFrame read_cylinder_frame(const std::filesystem::path& path) {
    return detail::frame_of(detail::read_frame_json(path), path);
}

CylinderFiles read_cylinder_files(const std::filesystem::path& exr_path) {
    const std::filesystem::path frame_path = exr_path.parent_path() / "frame.json";
    const nlohmann::json j = detail::read_frame_json(frame_path);
    CylinderFiles files{read_cylinder_exr(exr_path), detail::frame_of(j, frame_path)};
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

// The files a hierarchy lives in: hierarchy.exr (t, mask), hierarchy.png and frame.json.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"
#include "gimg/geometry/image.h"

#include "cylinder/frame_json.h"
#include "launch_rays.h"
#include "json_problem.h"

#include <algorithm>
#include <cmath>

namespace gimg::passes {

namespace {

// Each band rescaled to its own largest |t| (the thesis's fig. 3.9: later levels hold small
// values), warm for t > 0, cold for t < 0, black where invalid.
geo::RgbaImage hierarchy_preview(const CylinderHierarchy& h) {
    const std::uint32_t n = h.size;
    auto band_of = [&](std::uint32_t u, std::uint32_t v) {
        std::uint32_t s = h.base;
        if (u < s && v < s) return 0u;
        std::uint32_t level = 1;
        while (u >= s || v >= s) s *= 2, ++level;
        return 3 * level + (u >= s / 2 ? 1u : 0u) + (v >= s / 2 ? 2u : 0u);
    };
    std::vector<float> largest(64, 0.0f);
    for (std::uint32_t v = 0; v < n; ++v)
        for (std::uint32_t u = 0; u < n; ++u)
            if (h.valid[std::size_t(v) * n + u])
                largest[band_of(u, v)] = std::max(largest[band_of(u, v)], std::abs(h.t[std::size_t(v) * n + u]));
    geo::RgbaImage out(n, n);
    for (std::uint32_t v = 0; v < n; ++v)
        for (std::uint32_t u = 0; u < n; ++u) {
            const std::size_t i = std::size_t(v) * n + u;
            std::uint8_t* p = &out.pixels[4 * i];
            p[3] = 255;
            if (!h.valid[i]) continue;
            const float m = largest[band_of(u, v)];
            const float b = 0.15f + 0.85f * (m > 0.0f ? std::abs(h.t[i]) / m : 0.0f);
            const float warm[3] = {1.0f, 0.86f, 0.62f}, cold[3] = {0.50f, 0.76f, 1.0f};
            const float* hue = h.t[i] >= 0.0f ? warm : cold;
            for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(std::lround(255.0f * b * hue[c]));
        }
    return out;
}

}  // namespace

void write_hierarchy_files(const std::filesystem::path& dir, const CylinderHierarchy& h, const CylinderFrame& frame,
                           const CylinderFileInfo& info) {
    std::error_code ec;
    if (std::filesystem::exists(dir, ec))
        for (const char* name : {"hierarchy.exr", "hierarchy.png", "frame.json"}) geo::check_output_target(dir / name);
    ec = geo::create_output_folder(dir);
    if (ec) throw geo::InputError("cannot create folder " + dir.string() + ": " + ec.message());
    geo::FloatImage exr;
    exr.width = exr.height = h.size;
    auto& t = exr.channels["t"];
    auto& mask = exr.channels["mask"];
    t.resize(h.t.size());
    mask.resize(h.t.size());
    for (std::size_t i = 0; i < t.size(); ++i) {
        t[i] = h.valid[i] ? h.t[i] : 0.0f;
        mask[i] = h.valid[i] == kHierarchyHit      ? 1.0f
                  : h.valid[i] == kHierarchyRadial ? 0.75f
                  : h.valid[i] == kHierarchyMiss   ? 0.5f
                                                   : 0.0f;
    }
    geo::OutputSet files;
    geo::write_exr(exr, dir / "hierarchy.exr");
    geo::write_png(hierarchy_preview(h), dir / "hierarchy.png");
    nlohmann::json j = detail::frame_json(frame);
    j["hierarchy"] = {
        {"base", h.base},
        {"size", h.size},
        {"levels", h.levels()},
        {"reach", h.reach},
        {"mask",
         "1 hit, 0.75 a radial ray's hit (t from the wall), 0.5 a ray that found nothing within reach (kept on "
         "the interpolated surface), 0 empty"},
        {"layout",
         "level 1 top-left; level L: horizontal band right, vertical below, diagonal "
         "bottom-right"},
        {"level_1", "t = 1 - d along the inward radial ray"},
        {"later_levels",
         "signed distance along the outward normal of the launch point; radial samples (mask 0.75) the distance "
         "from the wall at their column's angle and their row's height"},
        {"rows", "row j of a grid of side S at height 1 - (j B / S + 0.5) / B, plus 1 where that is not above 0"}};
    j["source"] = info.source;
    j["method"] = info.method;
    j["image_stamp"] = detail::stamp_of(h.size, h.size, h.valid, h.t);
    geo::write_file_atomically(dir / "frame.json", j.dump(2) + "\n");
    files.commit();
}

HierarchyFiles read_hierarchy_files(const std::filesystem::path& exr_path) {
    const std::filesystem::path frame_path = exr_path.parent_path() / "frame.json";
    const nlohmann::json j = detail::read_frame_json(frame_path);
    HierarchyFiles files{{}, detail::frame_of(j, frame_path)};
    if (!j.contains("hierarchy"))
        throw geo::InputError(frame_path.string() + " describes no hierarchy (no \"hierarchy\" key)");
    const geo::FloatImage exr = geo::read_exr(exr_path);
    auto t = exr.channels.find("t");
    auto mask = exr.channels.find("mask");
    if (t == exr.channels.end() || mask == exr.channels.end())
        throw geo::InputError(exr_path.string() + " lacks channel \"t\" or \"mask\": not a gimg hierarchy");
    CylinderHierarchy& h = files.hierarchy;
    try {
        h.base = j.at("hierarchy").at("base").get<std::uint32_t>();
        h.size = j.at("hierarchy").at("size").get<std::uint32_t>();
        h.reach = j.at("hierarchy").value("reach", 0.0);
    } catch (const nlohmann::json::exception& e) {
        throw geo::InputError(frame_path.string() + ": bad \"hierarchy\": " + detail::json_problem(e));
    }
    check_hierarchy_sizes(h.base, h.size);
    if (exr.width != h.size || exr.height != h.size)
        throw geo::InputError(frame_path.string() + " describes a " + std::to_string(h.size) + "x" +
                              std::to_string(h.size) + " hierarchy, " + exr_path.string() + " is " +
                              std::to_string(exr.width) + "x" + std::to_string(exr.height));
    h.t.resize(t->second.size());
    h.valid.resize(t->second.size());
    for (std::size_t i = 0; i < h.t.size(); ++i) {
        const float m = mask->second[i], v = t->second[i];
        if (m != 0.0f && m != 0.5f && m != 0.75f && m != 1.0f)
            throw geo::InputError(exr_path.string() + ": mask = " + std::to_string(m) + " at pixel " +
                                  std::to_string(i) + " (it must be 0, 0.5, 0.75 or 1)");
        if (m != 0.0f && !(std::abs(v) <= 4.0f))
            throw geo::InputError(exr_path.string() + ": t = " + std::to_string(v) + " at pixel " + std::to_string(i) +
                                  " (a distance inside the cylinder is at most 4)");
        h.valid[i] = m == 1.0f    ? kHierarchyHit
                     : m == 0.75f ? kHierarchyRadial
                     : m == 0.5f  ? kHierarchyMiss
                                  : kHierarchyEmpty;
        h.t[i] = h.valid[i] ? v : 0.0f;
    }
    if (j.value("image_stamp", std::string()) != detail::stamp_of(h.size, h.size, h.valid, h.t))
        throw geo::InputError(exr_path.string() + " is not the hierarchy " + frame_path.string() +
                              " was written with (an interrupted or concurrent run?)");
    return files;
}

}  // namespace gimg::passes

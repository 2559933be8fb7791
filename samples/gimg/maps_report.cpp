// The wavelet half of `gimg maps`, its errors, pictures and file (maps_report.h).
#include "maps_report.h"

#include "command_files.h"
#include "timing.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"
#include "gimg/passes/render.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

namespace gimg::cli {

int parse_wavelet_k(const std::string& text) {
    if (text == "lazy") return -1;
    if (text == "0" || text == "1" || text == "2") return text[0] - '0';
    throw geo::InputError("--k takes lazy, 0, 1 or 2, got '" + text + "'");
}

namespace {

geo::Mesh mesh_of(const passes::SemiRegularMesh& remesh, std::uint32_t level, const std::vector<glm::dvec3>& values) {
    geo::Mesh m;
    m.positions.assign(values.begin(), values.begin() + remesh.vertex_count[level]);
    m.triangles = remesh.faces[level];
    return m;
}

}  // namespace

MapsWavelets maps_wavelets(Context* ctx, const passes::SemiRegularMesh& remesh, int k, double fraction) {
    MapsWavelets w;
    w.k = k;
    const std::uint32_t levels = remesh.levels();
    passes::WaveletFilters filters;
    w.filter_seconds = time_ms([&] { filters = passes::wavelet_filters(remesh, k); }) / 1e3;
    // The filters go to the device once, with the first transform (and in its time).
    std::optional<passes::WaveletBuffers> uploaded;
    auto on_device = [&]() -> passes::WaveletBuffers& {
        if (!uploaded) uploaded = passes::upload_wavelet_filters(*ctx, remesh, filters);
        return *uploaded;
    };
    auto analysis = [&](std::vector<glm::dvec3> x, std::uint32_t down_to) {
        if (ctx) return passes::wavelet_analysis_gpu(*ctx, remesh, on_device(), x, down_to);
        passes::wavelet_analysis(remesh, filters, x, down_to);
        return x;
    };
    auto synthesis = [&](std::vector<glm::dvec3> x) {
        if (ctx) return passes::wavelet_synthesis_gpu(*ctx, remesh, on_device(), x);
        passes::wavelet_synthesis(remesh, filters, x);
        return x;
    };
    // A remesh too large for the device's texel arrays runs on the CPU twin.
    if (ctx && !passes::wavelets_fit_device(*ctx, remesh, filters)) ctx = nullptr;
    w.on_gpu = ctx != nullptr;
    w.analysis_seconds = time_ms([&] { w.coefficients = analysis(remesh.positions, 0); }) / 1e3;
    std::vector<glm::dvec3> back;
    w.synthesis_seconds = time_ms([&] { back = synthesis(w.coefficients); }) / 1e3;
    double worst = 0.0;
    for (std::size_t i = 0; i < back.size(); ++i) worst = std::max(worst, glm::length(back[i] - remesh.positions[i]));
    const geo::Mesh finest = mesh_of(remesh, levels, remesh.positions);
    const double diagonal = finest.bounds().diagonal();
    w.reconstruction_error = diagonal > 0.0 ? worst / diagonal : worst;
    w.coarse = mesh_of(remesh, levels - 1, analysis(remesh.positions, levels - 1));
    w.details = remesh.positions.size() - remesh.vertex_count[0];
    if (fraction > 0.0) {
        std::vector<glm::dvec3> kept = w.coefficients;
        w.kept = passes::keep_largest_details(remesh, kept, fraction);
        w.compressed = mesh_of(remesh, levels, synthesis(kept));
    }
    return w;
}

MapsErrors maps_errors(const geo::Mesh& mesh, const passes::MapsRemesh& r, const MapsWavelets& w,
                       const geo::SurfaceDistanceOptions& options, ProgressLine* line) {
    MapsErrors e;
    const std::uint32_t levels = r.remesh.levels();
    auto measure = [&](const geo::Mesh& m, const std::string& what) {
        geo::SurfaceDistanceOptions o = options;
        if (line) o.progress = [&](double done) { line->percent(what.c_str(), done); };
        return geo::surface_distance(mesh, m, o);
    };
    for (std::uint32_t j = 1; j <= levels; ++j)
        e.levels.push_back(measure(r.remesh.level_mesh(j), "distance of level " + std::to_string(j)));
    e.coarse = measure(w.coarse, "distance of the one-level-down mesh");
    if (!w.compressed.triangles.empty()) e.compressed = measure(w.compressed, "distance of the compressed mesh");
    return e;
}

void write_wavelets(const passes::SemiRegularMesh& remesh, int k, const std::vector<glm::dvec3>& coefficients,
                    const std::filesystem::path& path) {
    std::string bytes;
    auto put = [&](const auto& value) {
        const char* p = reinterpret_cast<const char*>(&value);
        bytes.append(p, sizeof(value));
    };
    bytes.append("GIMGMAPS", 8);
    put(std::uint32_t(remesh.levels()));
    put(std::int32_t(k));
    put(std::uint32_t(remesh.vertex_count[0]));
    put(std::uint32_t(remesh.faces[0].size()));
    for (std::uint32_t v = 0; v < remesh.vertex_count[0]; ++v)
        for (int c = 0; c < 3; ++c) put(coefficients[v][c]);
    for (const glm::uvec3& t : remesh.faces[0])
        for (int c = 0; c < 3; ++c) put(std::uint32_t(t[c]));
    for (std::uint32_t j = 0; j < remesh.levels(); ++j) {
        put(std::uint32_t(remesh.vertex_count[j + 1] - remesh.vertex_count[j]));
        for (std::uint32_t m = remesh.vertex_count[j]; m < remesh.vertex_count[j + 1]; ++m) {
            const glm::uvec2 p = remesh.parents[m - remesh.vertex_count[0]];
            put(std::uint32_t(p.x));
            put(std::uint32_t(p.y));
            for (int c = 0; c < 3; ++c) put(coefficients[m][c]);
        }
    }
    geo::write_file_atomically(path, bytes);
}

namespace {

// Panels of equal height side by side.
geo::RgbaImage side_by_side(const std::vector<geo::RgbaImage>& panels) {
    std::uint32_t width = 0;
    for (const auto& p : panels) width += p.width;
    geo::RgbaImage out(width, panels.front().height);
    std::uint32_t x0 = 0;
    for (const auto& p : panels) {
        for (std::uint32_t y = 0; y < p.height; ++y) std::memcpy(out.at(x0, y), p.at(0, y), std::size_t(p.width) * 4);
        x0 += p.width;
    }
    for (std::size_t i = 3; i < out.pixels.size(); i += 4) out.pixels[i] = 255;
    return out;
}

}  // namespace

void write_maps_pictures(Context& ctx, const geo::Mesh& mesh, const passes::MapsRemesh& r, const MapsWavelets& w,
                         std::uint32_t panel, const std::filesystem::path& dir) {
    passes::RenderOptions view;
    view.width = view.height = panel;
    const passes::Camera camera = passes::fit_camera(mesh.positions, view.view, 1.0);
    // The original, each vertex coloured by the base triangle it maps into (golden-ratio hues).
    passes::RenderOptions patches = view;
    patches.color = passes::MeshColor::Scalar;
    patches.scalar_range = std::pair<float, float>(0.0f, 1.0f);
    for (const passes::SurfacePoint& p : r.domain.param)
        patches.scalars.push_back(float(std::fmod(double(p.face) * 0.6180339887, 1.0)));
    passes::RenderOptions edges = view;
    edges.wireframe = true;
    edges.smooth = false;
    const geo::RgbaImage base = side_by_side(
        {passes::render_mesh(ctx, mesh, patches, camera), passes::render_mesh(ctx, r.domain.base, edges, camera)});
    check_picture_shows_something(base, "the base domain");
    geo::write_png(base, dir / "base.png");
    // Levels beyond a million faces would draw as solid edges (and can exceed one device binding).
    constexpr std::size_t kMostFaces = 1'000'000;
    std::vector<geo::RgbaImage> levels;
    for (std::uint32_t j = 1; j <= r.remesh.levels(); ++j)
        if (r.remesh.faces[j].size() <= kMostFaces)
            levels.push_back(passes::render_mesh(ctx, r.remesh.level_mesh(j), edges, camera));
    passes::RenderOptions smooth = view;
    if (w.coarse.face_count() <= kMostFaces) levels.push_back(passes::render_mesh(ctx, w.coarse, smooth, camera));
    geo::write_png(side_by_side(levels), dir / "remesh.png");
}

void print_maps_report(const geo::Mesh& mesh, const passes::MapsRemesh& r, const MapsWavelets& w, const MapsErrors& e) {
    std::size_t skipped = 0;
    for (const auto& l : r.domain.levels) skipped += l.skipped;
    std::printf("base domain: %zu vertices, %zu faces after %zu levels (%.3f s; %zu removals refused by a guard)\n",
                r.domain.base.vertex_count(), r.domain.base.face_count(), r.domain.levels.size(), r.base_seconds,
                skipped);
    std::printf(
        "remesh: subdivision %.3f s, point location %.3f s, evaluation %.3f s, smoothing %.3f s; %zu "
        "straddling triangles, %zu unplaced, %zu inverted, %zu points placed by fallback\n",
        r.subdivide_seconds, r.locate_seconds, r.evaluate_seconds, r.smoothing_seconds, r.map.straddling,
        r.map.unplaced, r.map.inverted, r.fallbacks);
    for (std::size_t j = 0; j < e.levels.size(); ++j)
        std::printf("  level %zu: %7u vertices %8zu faces, RMS %.3e, Hausdorff %.3e of the diagonal\n", j + 1,
                    r.remesh.vertex_count[j + 1], r.remesh.faces[j + 1].size(),
                    e.levels[j].relative(e.levels[j].symmetric).rms, e.levels[j].relative(e.levels[j].symmetric).max);
    std::printf(
        "wavelets (k = %d): filters %.3f s, analysis %.3f s, synthesis %.3f s, reconstruction error %.1e; "
        "one level down RMS %.3e\n",
        w.k, w.filter_seconds, w.analysis_seconds, w.synthesis_seconds, w.reconstruction_error,
        e.coarse.relative(e.coarse.symmetric).rms);
    if (!w.compressed.triangles.empty())
        std::printf("compressed: %zu of %zu details kept, RMS %.3e, Hausdorff %.3e of the diagonal\n", w.kept,
                    w.details, e.compressed.relative(e.compressed.symmetric).rms,
                    e.compressed.relative(e.compressed.symmetric).max);
    (void)mesh;
}

nlohmann::json maps_json(const geo::Mesh& mesh, const passes::MapsRemesh& r, const MapsWavelets& w,
                         const MapsErrors& e) {
    auto distance = [](const geo::SurfaceDistance& d) {
        return nlohmann::json{{"rms", d.relative(d.symmetric).rms}, {"hausdorff", d.relative(d.symmetric).max}};
    };
    nlohmann::json hierarchy = nlohmann::json::array();
    for (const auto& l : r.domain.levels)
        hierarchy.push_back({{"vertices", l.vertices},
                             {"removed", l.removed},
                             {"candidates", l.candidates},
                             {"skipped", l.skipped},
                             {"seconds", l.seconds}});
    nlohmann::json levels = nlohmann::json::array();
    for (std::size_t j = 0; j < e.levels.size(); ++j) {
        nlohmann::json l = distance(e.levels[j]);
        l["level"] = j + 1;
        l["vertices"] = r.remesh.vertex_count[j + 1];
        l["faces"] = r.remesh.faces[j + 1].size();
        levels.push_back(l);
    }
    nlohmann::json j{{"vertices", mesh.vertex_count()},
                     {"faces", mesh.face_count()},
                     {"base_vertices", r.domain.base.vertex_count()},
                     {"base_faces", r.domain.base.face_count()},
                     {"hierarchy", hierarchy},
                     {"remesh", levels},
                     {"straddling", r.map.straddling},
                     {"unplaced", r.map.unplaced},
                     {"inverted", r.map.inverted},
                     {"fallbacks", r.fallbacks},
                     {"seconds",
                      {{"base_domain", r.base_seconds},
                       {"subdivide", r.subdivide_seconds},
                       {"point_location", r.locate_seconds},
                       {"evaluate", r.evaluate_seconds},
                       {"smoothing", r.smoothing_seconds},
                       {"wavelet_filters", w.filter_seconds},
                       {"analysis", w.analysis_seconds},
                       {"synthesis", w.synthesis_seconds}}},
                     {"wavelets_on", w.on_gpu ? "gpu" : "cpu"},
                     {"reconstruction_error", w.reconstruction_error},
                     {"coarse", distance(e.coarse)}};
    if (!w.compressed.triangles.empty()) {
        j["compressed"] = distance(e.compressed);
        j["compressed"]["kept"] = w.kept;
        j["compressed"]["details"] = w.details;
    }
    return j;
}

}  // namespace gimg::cli

// gimg reconstruct GI.exr --out MESH.ply [--threshold T|off] [--fill-caps] [--lod K] [--cpu] [--json FILE]
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/cylinder_hierarchy.h"
#include "gimg/passes/reconstruct.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace gimg::cli {

namespace {

struct ReconstructCliOptions {
    std::string image, out, threshold, json;
    bool fill_caps = false, cpu = false;
    std::uint32_t lod = 0;
};

std::optional<float> parse_threshold(const std::string& text) {
    if (text.empty()) return std::nullopt;
    if (text == "off") return std::numeric_limits<float>::infinity();
    // Decimal only (no hex, no inf or nan), and representable: 1e-400 is not a float, nor 0 by another name.
    const bool decimal = text.find_first_not_of("0123456789.eE+-") == std::string::npos;
    char* end = nullptr;
    errno = 0;
    const double t = std::strtod(text.c_str(), &end);
    const bool in_range = errno == 0 && t <= double(std::numeric_limits<float>::max()) &&
                          (t == 0.0 || t >= double(std::numeric_limits<float>::min()));
    if (!decimal || end == text.c_str() || *end != '\0' || !(t >= 0.0) || !in_range)
        throw geo::InputError("--threshold takes a distance from 0 to 3.4e38 or 'off', got '" + text + "'");
    return float(t);
}

// hierarchy.exr (cylinder --method hierarchical): decoded at its last level, or --lod K levels up.
void run_hierarchy_reconstruct(const ReconstructCliOptions& o, const GlobalOptions& global) {
    if (o.fill_caps) throw geo::InputError("--fill-caps is for cylindrical images, not hierarchies");
    const std::optional<float> threshold = parse_threshold(o.threshold);
    const passes::HierarchyFiles files = passes::read_hierarchy_files(o.image);
    const std::uint32_t levels = files.hierarchy.levels();
    if (o.lod >= levels)
        throw geo::InputError("--lod " + std::to_string(o.lod) + ": the hierarchy has " + std::to_string(levels) +
                              " levels");
    std::shared_ptr<Context> ctx;
    if (!o.cpu) ctx = open_context(global);
    geo::Mesh mesh;
    passes::HierarchyGrid grid;
    double longest = 0.0;  // the longest side a block keeps
    const double ms = time_ms([&] {
        grid = ctx ? passes::decode_cylinder_hierarchy_gpu(*ctx, files.hierarchy, levels - o.lod)
                   : passes::decode_cylinder_hierarchy(files.hierarchy, levels - o.lod);
        longest = threshold ? double(*threshold) : passes::default_hierarchy_threshold(grid);
        mesh = passes::hierarchy_mesh(grid, files.frame, longest);
    });
    if (mesh.face_count() == 0)
        throw geo::InputError(o.image + ": nothing to reconstruct: no block of four valid samples at level " +
                              std::to_string(levels - o.lod) +
                              " with sides within the threshold (try --threshold off)");
    geo::save_mesh(mesh, o.out);
    if (!global.quiet)
        std::printf("%s: hierarchy %ux%u, level %u -> %zu vertices, %zu triangles in %.2f ms\nwrote %s\n",
                    o.image.c_str(), grid.side, grid.side, levels - o.lod, mesh.vertex_count(), mesh.face_count(), ms,
                    o.out.c_str());
    nlohmann::json j{{"image", o.image},
                     {"out", o.out},
                     {"kind", "hierarchy"},
                     {"threshold", std::isinf(longest) ? nlohmann::json("off") : nlohmann::json(longest)},
                     {"width", grid.side},
                     {"height", grid.side},
                     {"lod", o.lod},
                     {"level", levels - o.lod},
                     {"levels", levels},
                     {"vertices", mesh.vertex_count()},
                     {"faces", mesh.face_count()},
                     {"method", ctx ? "gpu" : "cpu"},
                     {"seconds", ms / 1000.0}};
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

void run_reconstruct(const ReconstructCliOptions& o, const GlobalOptions& global) {
    const std::filesystem::path image_path = o.image;
    passes::ReconstructOptions options;
    options.threshold = parse_threshold(o.threshold);
    options.fill_caps = o.fill_caps;
    options.lod = o.lod;
    const geo::FloatImage probe = geo::read_exr(image_path);
    if (probe.channels.count("t") != 0) return run_hierarchy_reconstruct(o, global);
    const bool cylindrical = probe.channels.count("d") != 0;
    std::shared_ptr<Context> ctx;
    if (!o.cpu) ctx = open_context(global);
    passes::ReconstructStats stats;
    geo::Mesh mesh;
    const double ms = time_ms([&] {
        if (cylindrical) {
            const passes::CylinderFiles files = passes::read_cylinder_files(image_path);
            mesh = o.cpu ? passes::reconstruct_cpu(files.image, files.frame, options, &stats)
                         : passes::reconstruct_gpu(*ctx, files.image, files.frame, options, &stats);
        } else {
            const passes::PositionImage image = passes::read_position_exr(image_path);
            mesh = o.cpu ? passes::reconstruct_cpu(image, options, &stats)
                         : passes::reconstruct_gpu(*ctx, image, options, &stats);
        }
    });
    if (mesh.face_count() == 0)
        throw geo::InputError(o.image + ": nothing to reconstruct: " +
                              (mesh.vertex_count() == 0 ? std::string("no pixel is covered")
                               : stats.holes > 0
                                   ? "every block of four covered pixels is cut by the threshold " +
                                         std::to_string(stats.threshold) + " (try a larger --threshold or off)"
                                   : std::string("no 2x2 block of covered pixels")));
    geo::save_mesh(mesh, o.out);
    if (!global.quiet) {
        std::printf("%s: %s image %ux%u -> %zu vertices, %zu triangles, %zu holes (threshold %g) in %.2f ms",
                    o.image.c_str(), cylindrical ? "cylindrical" : "position", stats.width, stats.height,
                    mesh.vertex_count(), mesh.face_count(), stats.holes, double(stats.threshold), ms);
        if (ctx) std::printf(" (%.2f ms GPU)", stats.gpu_ms);
        std::printf("\nwrote %s\n", o.out.c_str());
    }
    nlohmann::json j{
        {"image", o.image},
        {"out", o.out},
        {"kind", cylindrical ? "cylindrical" : "position"},
        {"width", stats.width},
        {"height", stats.height},
        {"lod", o.lod},
        {"vertices", mesh.vertex_count()},
        {"faces", mesh.face_count()},
        {"holes", stats.holes},
        {"threshold", std::isfinite(stats.threshold) ? nlohmann::json(stats.threshold) : nlohmann::json("off")},
        {"fill_caps", o.fill_caps},
        {"method", o.cpu ? "cpu" : "gpu"},
        {"seconds", ms / 1000.0}};
    if (ctx) j["gpu_ms"] = stats.gpu_ms;
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

// The geometry image a folder written by gimg holds (cylinder, cylinder --method hierarchical, gim),
// so that `reconstruct DIR` works after `cylinder ... --out DIR`; other paths stay as given.
std::filesystem::path geometry_image_in(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_directory(path, ec)) return path;
    std::vector<std::filesystem::path> found;
    for (const char* name : {"distance.exr", "hierarchy.exr", "gim.exr"})
        if (std::filesystem::is_regular_file(path / name, ec)) found.push_back(path / name);
    if (found.size() == 1) return found.front();
    if (found.empty())
        throw geo::InputError(path.string() +
                              " is a folder without a geometry image (distance.exr, hierarchy.exr or gim.exr): "
                              "give the image file");
    std::string names;
    for (const auto& f : found) names += (names.empty() ? "" : " and ") + f.filename().string();
    throw geo::InputError(path.string() + " holds " + names + ": give the one to reconstruct");
}

}  // namespace

void add_reconstruct_command(CLI::App& app, const GlobalOptions& global) {
    auto opts = std::make_shared<ReconstructCliOptions>();
    auto* cmd =
        app.add_subcommand("reconstruct", "Turn a geometry image (cylindrical or position EXR) back into a mesh");
    cmd->add_option("image", opts->image,
                    "GI.exr: channel d with frame.json beside it, or channels R, G, B (and A); or the folder "
                    "cylinder or gim wrote")
        ->required();
    cmd->add_option("--out", opts->out, "Output mesh (.ply or .obj), with normals")->required();
    cmd->add_option("--threshold", opts->threshold,
                    "Largest distance jump inside a 2x2 block before it becomes a hole, or 'off' (default: six "
                    "pixel pitches for cylindrical images, off for position images; for hierarchies the longest side "
                    "of a block, default twelve pitches)");
    cmd->add_flag("--fill-caps", opts->fill_caps, "Close the top and bottom openings (cylindrical images)");
    add_count_option(cmd, "--lod", opts->lod, 0, 14, "Reduce the image K times (2x2 means of valid pixels) first");
    cmd->add_flag("--cpu", opts->cpu, "Use the CPU reference instead of the GPU passes (same output)");
    cmd->add_option("--json", opts->json, "Write the figures as JSON");
    cmd->callback([opts, &global] {
        const std::filesystem::path image = geometry_image_in(opts->image);
        opts->image = image.string();
        run_writing({image, image.parent_path() / "frame.json"},
                    {{"--out", opts->out, {".ply", ".obj"}}, json_output(opts->json)},
                    [&] { run_reconstruct(*opts, global); });
    });
}

}  // namespace gimg::cli

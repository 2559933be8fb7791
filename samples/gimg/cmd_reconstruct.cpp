// gimg reconstruct GI.exr --out MESH.ply [--threshold T|off] [--fill-caps] [--lod K] [--cpu] [--json FILE]
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/reconstruct.h"

#include <cmath>
#include <cstdio>
#include <limits>

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
    char* end = nullptr;
    const float t = std::strtof(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !(t >= 0.0f))
        throw geo::InputError("--threshold takes a distance >= 0 or 'off', got '" + text + "'");
    return t;
}

void run_reconstruct(const ReconstructCliOptions& o, const GlobalOptions& global) {
    const std::filesystem::path image_path = o.image;
    passes::ReconstructOptions options;
    options.threshold = parse_threshold(o.threshold);
    options.fill_caps = o.fill_caps;
    options.lod = o.lod;
    const geo::FloatImage probe = geo::read_exr(image_path);
    const bool cylindrical = probe.channels.count("d") != 0;
    std::unique_ptr<Context> ctx;
    if (!o.cpu) ctx = open_context(global);
    passes::ReconstructStats stats;
    geo::Mesh mesh;
    const double ms = time_ms([&] {
        if (cylindrical) {
            const auto frame_path = image_path.parent_path() / "frame.json";
            const passes::CylinderFrame frame = passes::read_cylinder_frame(frame_path);
            const passes::CylinderImage image = passes::read_cylinder_exr(image_path);
            mesh = o.cpu ? passes::reconstruct_cpu(image, frame, options, &stats)
                         : passes::reconstruct_gpu(*ctx, image, frame, options, &stats);
        } else {
            const passes::PositionImage image = passes::read_position_exr(image_path);
            mesh = o.cpu ? passes::reconstruct_cpu(image, options, &stats)
                         : passes::reconstruct_gpu(*ctx, image, options, &stats);
        }
    });
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

}  // namespace

void add_reconstruct_command(CLI::App& app, const GlobalOptions& global) {
    auto opts = std::make_shared<ReconstructCliOptions>();
    auto* cmd =
        app.add_subcommand("reconstruct", "Turn a geometry image (cylindrical or position EXR) back into a mesh");
    cmd->add_option("image", opts->image, "GI.exr: channel d with frame.json beside it, or channels R, G, B (and A)")
        ->required();
    cmd->add_option("--out", opts->out, "Output mesh (.ply or .obj), with normals")->required();
    cmd->add_option("--threshold", opts->threshold,
                    "Largest distance jump inside a 2x2 block before it becomes a hole, or 'off' (default: six "
                    "pixel pitches for cylindrical images, off for position images)");
    cmd->add_flag("--fill-caps", opts->fill_caps, "Close the top and bottom openings (cylindrical images)");
    cmd->add_option("--lod", opts->lod, "Reduce the image K times (2x2 means of valid pixels) first");
    cmd->add_flag("--cpu", opts->cpu, "Use the CPU reference instead of the GPU passes (same output)");
    cmd->add_option("--json", opts->json, "Write the figures as JSON");
    cmd->callback([opts, &global] { run_reconstruct(*opts, global); });
}

}  // namespace gimg::cli

// gimg roundtrip MESH --out DIR [--size WxH | --auto] [--samples N] [--json FILE]
// Cylinder (GPU), reconstruct (GPU), compare with the original both ways, and a picture of both.
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "progress_line.h"
#include "size_option.h"
#include "timing.h"

#include "gimg/geometry/io.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/cylinder_hierarchy.h"
#include "gimg/passes/reconstruct.h"
#include "gimg/passes/render.h"

#include <cstdio>

namespace gimg::cli {

namespace {
struct RoundtripOptions {
    std::string mesh, out, size, json;
    bool auto_size = false;
    std::uint64_t samples = 0;
    std::string method = "zbuffer";
};

nlohmann::json stats_json(const geo::DistanceStats& s) { return {{"mean", s.mean}, {"rms", s.rms}, {"max", s.max}}; }

void run_roundtrip(const RoundtripOptions& o, const GlobalOptions& global) {
    const std::string size_text = o.method == "hierarchical" && !o.size.empty() && o.size.find('x') == std::string::npos
                                      ? o.size + "x" + o.size
                                      : o.size;
    const std::optional<std::array<std::uint32_t, 2>> asked =
        size_text.empty() ? std::nullopt : std::optional(parse_size(size_text));
    // Reconstruction needs 2x2 pixels: refused before any work, and --auto never goes below 4x2.
    if (asked && ((*asked)[0] < 2 || (*asked)[1] < 2))
        throw geo::InputError("--size " + o.size + ": a roundtrip needs at least 2x2 pixels");
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    if (mesh.face_count() == 0) throw geo::InputError(o.mesh + " has no faces");
    const auto auto_size = passes::auto_cylinder_size(mesh.face_count());
    std::array<std::uint32_t, 2> wh =
        asked ? *asked : std::array<std::uint32_t, 2>{std::max(auto_size[0], 4u), std::max(auto_size[1], 2u)};
    if (o.method == "hierarchical" && !asked) wh = {256, 256};
    auto ctx = open_context(global);
    const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);

    passes::ReconstructStats stats;
    geo::Mesh back;
    double project_ms = 0.0, reconstruct_ms = 0.0, gpu_ms = 0.0;
    if (o.method == "hierarchical") {
        // A square hierarchy from 32 x 32 (or the image's side when smaller) up to --size N.
        const std::uint32_t n = wh[0];
        if (wh[0] != wh[1]) throw geo::InputError("--size: a hierarchy is square, got '" + o.size + "'");
        const std::uint32_t base = std::min(32u, n);
        passes::check_hierarchy_sizes(base, n);
        passes::CylinderHierarchy h;
        project_ms = time_ms([&] {
            h = passes::cylinder_hierarchy_cpu(passes::make_cylinder_mesh(mesh, frame), {.base = base, .size = n});
        });
        passes::write_hierarchy_files(o.out, h, frame, {o.mesh, "hierarchical"});
        reconstruct_ms =
            time_ms([&] { back = passes::hierarchy_mesh(passes::decode_cylinder_hierarchy(h, h.levels()), frame); });
        stats.width = stats.height = n;
    } else {
        passes::CylinderZBuffer zbuffer(*ctx, wh[0], wh[1], {.timestamps = true});
        passes::CylinderImage image;
        project_ms =
            time_ms([&] { image = zbuffer.project(zbuffer.add_mesh(passes::make_cylinder_mesh(mesh, frame))); });
        passes::write_cylinder_files(o.out, image, frame, {o.mesh, "zbuffer"});
        reconstruct_ms = time_ms([&] { back = passes::reconstruct_gpu(*ctx, image, frame, {}, &stats); });
        gpu_ms = zbuffer.last_gpu_ms() + stats.gpu_ms;
    }
    passes::check_rebuilt_surface(back,
                                  o.mesh + ": the " + std::to_string(wh[0]) + "x" + std::to_string(wh[1]) + " image",
                                  "try a larger --size");
    geo::save_mesh(back, std::filesystem::path(o.out) / "reconstruction.ply");
    geo::SurfaceDistanceOptions so;
    if (o.samples) so.sampling.sample_count = o.samples;
    ProgressLine line(global.quiet);
    if (line.on()) so.progress = [&line](double done) { line.percent("surface distance", done); };
    const geo::SurfaceDistance d = geo::surface_distance(mesh, back, so);
    line.finish();
    passes::RenderOptions view;
    view.width = 640;
    view.height = 640;
    view.view.azimuth_deg = 200.0;
    view.view.elevation_deg = 15.0;
    geo::RgbaImage picture = passes::render_side_by_side(*ctx, mesh, back, view);
    check_picture_shows_something(picture, o.mesh);
    for (std::size_t i = 3; i < picture.pixels.size(); i += 4) picture.pixels[i] = 255;
    geo::write_png(picture, std::filesystem::path(o.out) / "compare.png");

    const double diag = d.bbox_diagonal;
    if (!global.quiet) {
        std::printf("%s: %zu faces -> %ux%u image (%.1f ms) -> %zu faces (%zu holes, %.1f ms)\n", o.mesh.c_str(),
                    mesh.face_count(), wh[0], wh[1], project_ms, back.face_count(), stats.holes, reconstruct_ms);
        std::printf(
            "relative to the bounding-box diagonal: RMS %.3e (original->reconstruction %.3e, back %.3e), "
            "Hausdorff %.3e\n",
            d.symmetric.rms / diag, d.a_to_b.rms / diag, d.b_to_a.rms / diag, d.symmetric.max / diag);
        std::printf("wrote %s/{%s, frame.json, reconstruction.ply, compare.png}\n", o.out.c_str(),
                    o.method == "hierarchical" ? "hierarchy.exr, hierarchy.png" : "distance.exr, distance.png");
    }
    nlohmann::json j{{"mesh", o.mesh},
                     {"faces", mesh.face_count()},
                     {"width", wh[0]},
                     {"height", wh[1]},
                     {"reconstruction_faces", back.face_count()},
                     {"holes", stats.holes},
                     {"a_to_b", stats_json(d.a_to_b)},
                     {"b_to_a", stats_json(d.b_to_a)},
                     {"symmetric", stats_json(d.symmetric)},
                     {"bbox_diagonal", diag},
                     {"symmetric_relative", stats_json(d.relative(d.symmetric))},
                     {"project_ms", project_ms},
                     {"reconstruct_ms", reconstruct_ms},
                     {"method", o.method},
                     {"gpu_ms", gpu_ms}};
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

}  // namespace

void add_roundtrip_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<RoundtripOptions>();
    auto* cmd = app.add_subcommand("roundtrip", "Mesh -> cylindrical image -> mesh, measured against the original");
    cmd->add_option("mesh", o->mesh, "Input mesh")->required();
    cmd->add_option("--out", o->out, "Output folder (distance.exr/png, frame.json, reconstruction.ply, compare.png)")
        ->required();
    auto* size = cmd->add_option("--size", o->size, "Image size WxH");
    cmd->add_flag("--auto", o->auto_size, "W = 2H with 2WH close to the face count (the default)")->excludes(size);
    add_count_option(cmd, "--samples", o->samples, 1, 100'000'000,
                     "Surface samples per mesh for the distance (default max(1M, 10 per face))");
    cmd->add_option("--method", o->method,
                    "zbuffer (the ordinary image on the GPU, default) or hierarchical (the thesis's chapter 3, N x N "
                    "from 32 x 32; --size N, default 256)")
        ->check(CLI::IsMember({"zbuffer", "hierarchical"}));
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] {
        auto outputs = folder_outputs("--out", o->out,
                                      o->method == "hierarchical"
                                          ? std::vector<std::string>{"hierarchy.exr", "hierarchy.png", "frame.json",
                                                                     "reconstruction.ply", "compare.png"}
                                          : std::vector<std::string>{"distance.exr", "distance.png", "frame.json",
                                                                     "reconstruction.ply", "compare.png"});
        outputs.push_back(json_output(o->json));
        run_writing({o->mesh}, outputs, [&] { run_roundtrip(*o, global); });
    });
}

}  // namespace gimg::cli

// gimg cylinder MESH --out DIR [--size WxH | --auto] [--method zbuffer|raycast|scanline] [--no-align] [--json FILE]
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "size_option.h"

#include "gimg/geometry/io.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/cylinder_hierarchy.h"

#include <chrono>
#include <cstdio>

namespace gimg::cli {

namespace {
struct CylinderOptions {
    std::string mesh, out, size, method = "zbuffer", json;
    bool auto_size = false, no_align = false;
    std::uint32_t base = 32;
    double reach = passes::CylinderHierarchyOptions{}.reach;
    std::string misses = "radial";
    bool cpu = false;
};

// --method hierarchical: the thesis's chapter 3, into DIR/hierarchy.exr, hierarchy.png, frame.json.
void run_hierarchy(const CylinderOptions& o, const GlobalOptions& global) {
    const auto start = std::chrono::steady_clock::now();
    std::uint32_t n = 256;
    if (!o.size.empty()) {
        const std::string text = o.size.find('x') == std::string::npos ? o.size + "x" + o.size : o.size;
        const auto wh = parse_size(text);
        if (wh[0] != wh[1]) throw geo::InputError("--size: a hierarchy is square (N or NxN), got '" + o.size + "'");
        n = wh[0];
    }
    passes::check_hierarchy_sizes(o.base, n);
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    if (mesh.face_count() == 0) throw geo::InputError(o.mesh + " has no faces to project");
    const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh, !o.no_align);
    // Per-level GPU times only for the JSON: timestamps cost lavapipe time.
    const passes::CylinderHierarchyOptions options{.base = o.base,
                                                   .size = n,
                                                   .reach = o.reach,
                                                   .miss = passes::hierarchy_miss(o.misses),
                                                   .timestamps = !o.json.empty()};
    std::shared_ptr<Context> ctx;
    if (!o.cpu) ctx = open_context(global);
    const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, frame);
    const passes::CylinderHierarchy h =
        ctx ? passes::cylinder_hierarchy_gpu(*ctx, cyl, options) : passes::cylinder_hierarchy_cpu(cyl, options);
    std::size_t valid = 0;
    for (auto v : h.valid) valid += v != passes::kHierarchyEmpty;  // hits, radial hits, misses kept on the surface
    if (valid == 0) throw geo::InputError(o.mesh + ": no ray of the hierarchy meets the model; try a larger --base");
    passes::write_hierarchy_files(o.out, h, frame, {o.mesh, "hierarchical"});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!global.quiet) {
        std::printf("%s: %zu faces -> %ux%u hierarchy from %ux%u (%u levels), %zu of %u samples valid; %.3f s\n",
                    o.mesh.c_str(), mesh.face_count(), n, n, o.base, o.base, h.levels(), valid, n * n, seconds);
        std::printf("wrote %s/{hierarchy.exr, hierarchy.png, frame.json}\n", o.out.c_str());
    }
    nlohmann::json j{{"mesh", o.mesh},         {"faces", mesh.face_count()}, {"size", n},
                     {"base", o.base},         {"levels", h.levels()},       {"method", "hierarchical"},
                     {"reach", o.reach},       {"misses", o.misses},         {"aligned", !o.no_align},
                     {"valid_samples", valid}, {"seconds", seconds},         {"scale", frame.scale}};
    j["encoder"] = ctx ? "gpu" : "cpu";
    j["level_ms"] = h.level_ms;
    j["tree_ms"] = h.tree_ms;
    if (ctx) j["pipeline_ms"] = h.pipeline_ms;
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

void run_cylinder(const CylinderOptions& o, const GlobalOptions& global) {
    if (o.method == "hierarchical") return run_hierarchy(o, global);
    const auto start = std::chrono::steady_clock::now();
    const std::optional<std::array<std::uint32_t, 2>> asked =
        o.size.empty() ? std::nullopt : std::optional(parse_size(o.size));
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    if (mesh.face_count() == 0) throw geo::InputError(o.mesh + " has no faces to project");
    const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh, !o.no_align);
    const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, frame);
    const auto size = asked ? *asked : passes::auto_cylinder_size(mesh.face_count());

    passes::CylinderImage image;
    std::shared_ptr<Context> ctx;
    double gpu_ms = 0.0;
    if (o.method == "zbuffer") {
        ctx = open_context(global);
        passes::CylinderZBuffer zbuffer(*ctx, size[0], size[1], {.timestamps = true});
        image = zbuffer.project(zbuffer.add_mesh(cyl));
        gpu_ms = zbuffer.last_gpu_ms();
    } else if (o.method == "raycast-gpu") {
        ctx = open_context(global);
        image = passes::cylinder_raycast_gpu(*ctx, cyl, size[0], size[1]);
    } else if (o.method == "scanline") {
        image = passes::cylinder_scanline(cyl, size[0], size[1]);
    } else {
        image = passes::cylinder_raycast(cyl, size[0], size[1]);
    }
    std::size_t covered = 0;
    for (auto c : image.covered) covered += c;
    if (covered == 0)
        throw geo::InputError(o.mesh + ": the projection covers no pixel at " + std::to_string(size[0]) + "x" +
                              std::to_string(size[1]) + " (faces too small or edge-on); try a larger --size");
    passes::write_cylinder_files(o.out, image, frame, {o.mesh, o.method});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    if (!global.quiet) {
        std::printf("%s: %zu faces -> %ux%u cylindrical image by %s%s%s\n", o.mesh.c_str(), mesh.face_count(), size[0],
                    size[1], o.method.c_str(), ctx ? " on " : "", ctx ? ctx->device_info().name.c_str() : "");
        std::printf("%zu of %u pixels covered; %.3f s", covered, size[0] * size[1], seconds);
        if (ctx) std::printf(", %.3f ms GPU", gpu_ms);
        std::printf("\nwrote %s/{distance.exr, distance.png, frame.json}\n", o.out.c_str());
    }
    nlohmann::json j{
        {"mesh", o.mesh},      {"faces", mesh.face_count()}, {"width", size[0]},          {"height", size[1]},
        {"method", o.method},  {"aligned", !o.no_align},     {"covered_pixels", covered}, {"seconds", seconds},
        {"scale", frame.scale}};
    if (ctx) j["gpu_ms"] = gpu_ms;
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}
}  // namespace

void add_cylinder_command(CLI::App& app, const GlobalOptions& global) {
    auto opts = std::make_shared<CylinderOptions>();
    auto* cmd = app.add_subcommand("cylinder", "Project a mesh into a cylindrical geometry image");
    cmd->add_option("mesh", opts->mesh, "Input mesh (OBJ, PLY, OFF, STL)")->required();
    cmd->add_option("--out", opts->out, "Output folder for distance.exr, distance.png and frame.json")->required();
    auto* size = cmd->add_option("--size", opts->size, "Image size WxH");
    cmd->add_flag("--auto", opts->auto_size, "W = 2H with 2WH close to the face count (the default)")->excludes(size);
    cmd->add_option(
           "--method", opts->method,
           "zbuffer (GPU, default), raycast (CPU reference), raycast-gpu (the same rays on the GPU), scanline (the "
           "paper's CPU algorithm) or "
           "hierarchical (the thesis's chapter 3: levels of rays along the surface normal)")
        ->check(CLI::IsMember({"zbuffer", "raycast", "raycast-gpu", "scanline", "hierarchical"}));
    add_count_option(cmd, "--base", opts->base, 2, 8192, "hierarchical: level 1 is B x B (default 32)");
    add_number_option(cmd, "--reach", opts->reach, 0.0, 1e6,
                      "hierarchical: a ray goes at most this many times the distance between its parents (0: "
                      "without limit, as the thesis; default 8)");
    cmd->add_option("--misses", opts->misses,
                    "hierarchical: a ray that finds nothing within reach gives way to the ordinary image's ray at its "
                    "angle and height (radial, default), leaves a sample on the interpolated surface (surface) or a "
                    "hole (empty)")
        ->check(CLI::IsMember({"surface", "empty", "radial"}));
    cmd->add_flag("--cpu", opts->cpu, "hierarchical: cast on the CPU instead of the GPU (the same hierarchy)");
    cmd->add_flag("--no-align", opts->no_align, "Keep the model's orientation (no PCA), only centre and scale");
    cmd->add_option("--json", opts->json, "Write the figures as JSON");
    cmd->callback([opts, &global] {
        auto outputs = folder_outputs("--out", opts->out,
                                      opts->method == "hierarchical"
                                          ? std::vector<std::string>{"hierarchy.exr", "hierarchy.png", "frame.json"}
                                          : std::vector<std::string>{"distance.exr", "distance.png", "frame.json"});
        outputs.push_back(json_output(opts->json));
        run_writing({opts->mesh}, outputs, [&] { run_cylinder(*opts, global); });
    });
}

}  // namespace gimg::cli

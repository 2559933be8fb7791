// gimg sphere MESH --out DIR [--method harmonic|kanai|gu|linear] [--json FILE]
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "progress_line.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/image.h"
#include "gimg/engine/error.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/render.h"
#include "gimg/passes/sphere.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

namespace gimg::cli {

namespace {

struct SphereCliOptions {
    std::string mesh, out, method = "harmonic", json;
    passes::HarmonicSphereOptions harmonic;
};

nlohmann::json metrics_json(const passes::SphereMetrics& m) {
    return {{"flips", m.flips},
            {"conformal_energy", m.conformal_energy},
            {"conformal_ratio", m.conformal_ratio},
            {"angle_distortion_deg",
             {{"mean", m.angle_distortion_deg.mean},
              {"p95", m.angle_distortion_deg.p95},
              {"max", m.angle_distortion_deg.max}}},
            {"area_distortion", m.area_distortion},
            {"smallest_area", m.smallest_area}};
}

nlohmann::json stages_json(const std::vector<passes::SphereStage>& stages) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& s : stages)
        list.push_back({{"name", s.name},
                        {"vertices", s.vertices},
                        {"iterations", s.iterations},
                        {"seconds", s.seconds},
                        {"energy", s.energy}});
    return list;
}

// The sphere's points as a mesh (same connectivity), with the points as normals.
geo::Mesh sphere_mesh(const geo::Mesh& mesh, const std::vector<glm::dvec3>& y) {
    geo::Mesh out;
    out.positions = y;
    out.normals = y;
    out.triangles = mesh.triangles;
    return out;
}

void run_sphere(const SphereCliOptions& o, const GlobalOptions& global) {
    const auto start = std::chrono::steady_clock::now();
    if (!(o.harmonic.tolerance > 0.0) || !std::isfinite(o.harmonic.tolerance))
        throw geo::InputError("--tolerance takes a positive number (default 3e-6)");
    if (o.harmonic.max_iterations_per_level == 0) throw geo::InputError("--max-iterations takes a positive count");
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    passes::check_sphere_input(mesh);

    ProgressLine line(global.quiet);
    passes::SphereProgress progress;
    if (line.on())
        progress = [&line](const std::string& stage, std::size_t iteration, double energy, std::size_t flips,
                           double seconds) {
            line.show("%s  iteration %zu  energy %.6g  flips %zu  %.1f s", stage.c_str(), iteration, energy, flips,
                      seconds);
        };
    // The CPU methods run without a Vulkan device; the pictures need one.
    std::shared_ptr<Context> ctx;
    if (o.method == "harmonic") {
        ctx = open_context(global);
    } else {
        try {
            ctx = open_context(global);
        } catch (const gimg::Error& e) {
            if (!global.quiet)
                std::fprintf(stderr, "gimg: note: %s; checker.png and sphere.png are not drawn\n", e.what());
        }
    }
    passes::SphereResult result;
    const double solve_ms = time_ms([&] {
        if (o.method == "harmonic") {
            passes::HarmonicSphereOptions options = o.harmonic;
            options.progress = progress;
            result = passes::sphere_harmonic(*ctx, mesh, options);
        } else if (o.method == "kanai") {
            passes::KanaiOptions options;
            options.progress = progress;
            result = passes::sphere_kanai(mesh, options);
        } else if (o.method == "gu") {
            passes::GuOptions options;
            options.progress = progress;
            result = passes::sphere_gu(mesh, options);
        } else {
            result = passes::sphere_linear(mesh);
        }
    });
    line.finish();
    const passes::SphereMetrics m = passes::sphere_metrics(mesh, result.positions);

    const std::filesystem::path dir = o.out;
    make_output_folder("--out", dir);
    // float64: the tiniest triangles of a conformal map are below float32's resolution.
    geo::save_mesh(sphere_mesh(mesh, result.positions), dir / "sphere.ply", {.double_precision = true});
    if (ctx) write_sphere_pictures(*ctx, mesh, result.positions, dir);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    nlohmann::json j = metrics_json(m);
    j["mesh"] = o.mesh;
    j["method"] = o.method;
    j["vertices"] = mesh.vertex_count();
    j["faces"] = mesh.face_count();
    j["converged"] = result.converged;
    j["note"] = result.note;
    j["solve_seconds"] = solve_ms / 1000.0;
    j["seconds"] = seconds;
    j["stages"] = stages_json(result.stages);
    // Sweeps, queue pops or steps of the optimisation (the hierarchy's build and base map aside).
    std::size_t iterations = 0;
    for (const auto& s : result.stages)
        if (s.name != "progressive mesh" && s.name != "base map") iterations += s.iterations;
    j["iterations"] = iterations;
    if (result.gpu_ms > 0.0) j["gpu_ms"] = result.gpu_ms;
    add_machine_figures(j, o.method == "harmonic" ? ctx.get() : nullptr);
    gimg::geo::write_file_atomically(dir / "metrics.json", j.dump(2) + "\n");
    write_json(o.json, j);

    if (!global.quiet) {
        std::printf("%s: %zu vertices -> sphere by %s in %.3f s%s\n", o.mesh.c_str(), mesh.vertex_count(),
                    o.method.c_str(), solve_ms / 1000.0, result.converged ? "" : " (did not converge)");
        std::printf(
            "flips %zu, conformal energy %.4f (ratio %.5f), angle distortion mean %.3f / p95 %.3f / max %.2f deg, "
            "area distortion %.3f\n",
            m.flips, m.conformal_energy, m.conformal_ratio, m.angle_distortion_deg.mean, m.angle_distortion_deg.p95,
            m.angle_distortion_deg.max, m.area_distortion);
        if (!result.note.empty()) std::printf("note: %s\n", result.note.c_str());
        std::printf("wrote %s/{sphere.ply, metrics.json, checker.png, sphere.png}\n", o.out.c_str());
    }
}

}  // namespace

void write_sphere_pictures(Context& ctx, const geo::Mesh& mesh, const std::vector<glm::dvec3>& y,
                           const std::filesystem::path& dir) {
    passes::RenderOptions view;
    view.width = 800;
    view.height = 800;
    view.color = passes::MeshColor::Checker;
    view.checker_cells = 12.0;
    const geo::RgbaImage checker = passes::render_mesh(ctx, passes::spherical_texture_mesh(mesh, y), view);
    check_picture_shows_something(checker, "checker.png");
    geo::write_png(checker, dir / "checker.png");
    geo::Mesh on_sphere = mesh;
    on_sphere.positions = y;
    geo::write_png(passes::render_mesh(ctx, passes::spherical_texture_mesh(on_sphere, y), view), dir / "sphere.png");
}

void add_sphere_command(CLI::App& app, const GlobalOptions& global) {
    auto opts = std::make_shared<SphereCliOptions>();
    auto* cmd = app.add_subcommand("sphere", "Conformal map of a closed genus-0 mesh onto the unit sphere");
    cmd->add_option("mesh", opts->mesh, "Closed, manifold, genus-0 mesh (.off, .obj, .ply, .stl)")->required();
    cmd->add_option("--out", opts->out, "Output folder for sphere.ply, metrics.json, checker.png and sphere.png")
        ->required();
    cmd->add_option("--method", opts->method,
                    "harmonic (default: flip-free, on the render graph; `gpu` is an alias), kanai (Kanai's CPU "
                    "method), gu (Gu et al., CPU), linear (Choi-Lam-Lui 2015, CPU)")
        ->transform(CLI::Transformer(std::map<std::string, std::string>{{"gpu", "harmonic"}}))
        ->check(CLI::IsMember({"harmonic", "kanai", "gu", "linear"}));
    cmd->add_option(
        "--tolerance", opts->harmonic.tolerance,
        "harmonic: a level ends when the energy changes less than this per iteration, relative (default 3e-6)");
    add_count_option(cmd, "--max-iterations", opts->harmonic.max_iterations_per_level, 1, 100'000'000,
                     "harmonic: at most this many sweeps per level (default 4000)");
    cmd->add_flag_callback(
        "--no-polish", [opts] { opts->harmonic.plane_polish = false; },
        "harmonic: skip the harmonic map in a stereographic chart after the finest level (faster, "
        "protrusions stay crooked); implies --hierarchy");
    cmd->add_flag_callback(
        "--hierarchy", [opts] { opts->harmonic.direct = false; },
        "harmonic: skip the pinned-triangle start and relax on the progressive-mesh hierarchy at once");
    cmd->add_option("--json", opts->json, "Write the metrics and timings as JSON");
    cmd->callback([opts, &global] {
        auto outputs = folder_outputs("--out", opts->out, {"sphere.ply", "checker.png", "sphere.png", "metrics.json"});
        outputs.push_back(json_output(opts->json));
        run_writing({opts->mesh}, outputs, [&] { run_sphere(*opts, global); });
    });
}

}  // namespace gimg::cli

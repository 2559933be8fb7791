// gimg bench sphere [--mesh PATH]... [--method NAME]... [--runs N] [--gu-max-vertices N] [--json FILE]
//
// The spherical parameterizations on the same meshes in one process: harmonic (ours), linear (Choi,
// Lam and Lui 2015, Eigen), kanai (the paper's method, CPU) and gu (Gu et al., CPU, on meshes up
// to --gu-max-vertices; it often fails, as the paper's table 1 shows). Medians of N runs of the
// wall time, and the quality of the map: flips, conformal ratio, angle distortion.
#include "bench_paths.h"
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/sphere.h"

#include <cstdio>
#include <filesystem>
#include <map>

namespace gimg::cli {

namespace {

struct SphereBenchOptions {
    std::vector<std::string> meshes;
    std::vector<std::string> methods{"harmonic", "linear", "kanai", "gu"};
    std::uint32_t runs = 3;
    std::size_t gu_max_vertices = 10000;
    std::string json;
};

// Every closed genus-0 mesh of ../shared/meshes, then the fetched 104K and 151K-vertex ones.
std::vector<std::string> default_sphere_meshes() {
    std::vector<std::string> out;
    const auto shared = shared_mesh_dir();
    const auto large = large_mesh_dir();
    std::vector<std::filesystem::path> candidates;
    for (const char* name : {"hand.off", "bunny_small.obj", "blobby.off", "triceratops.off", "cow.off", "dino.off",
                             "homer.off", "fandisk.off", "camel.off", "armadillo.off", "bunny.off"})
        candidates.push_back(shared / name);
    candidates.push_back(large / "derived/armadillo_loop1.off");
    candidates.push_back(large / "derived/bunny_loop1.off");
    for (const auto& p : candidates) {
        if (std::filesystem::exists(p))
            out.push_back(p.string());
        else
            std::fprintf(
                stderr,
                "gimg bench sphere: skipping %s (not found; ../shared/meshes/fetch_large.sh fetches the large ones)\n",
                p.c_str());
    }
    return out;
}

passes::SphereResult solve(Context& ctx, const std::string& method, const geo::Mesh& mesh) {
    if (method == "harmonic") return passes::sphere_harmonic(ctx, mesh);
    if (method == "linear") return passes::sphere_linear(mesh);
    if (method == "kanai") return passes::sphere_kanai(mesh);
    return passes::sphere_gu(mesh);
}

void run_sphere_bench(const SphereBenchOptions& o, const GlobalOptions& global) {
    auto ctx = open_context(global);
    const int runs = int(o.runs);
    passes::sphere_harmonic(*ctx, geo::make_icosphere(1.0, 3));  // pipelines compile once, outside the timings
    std::printf("gimg bench sphere on %s; medians of %d runs\n", ctx->device_info().summary().c_str(), runs);
    std::printf("%-20s %7s %-7s %9s %6s %9s %8s %8s %9s %s\n", "mesh", "V", "method", "seconds", "flips", "ratio",
                "ang.mean", "ang.p95", "vs harmonic", "note");
    nlohmann::json j;
    j["runs"] = runs;
    const std::vector<std::string> meshes = o.meshes.empty() ? default_sphere_meshes() : o.meshes;
    for (const std::string& path : meshes) {
        const geo::Mesh mesh = geo::load_mesh(path);
        passes::check_sphere_input(mesh);
        const std::string name = std::filesystem::path(path).filename().string();
        std::map<std::string, double> seconds_of;
        for (const std::string& method : o.methods) {
            if (method == "gu" && mesh.vertex_count() > o.gu_max_vertices) continue;
            std::vector<double> wall;
            passes::SphereResult result;
            for (int k = 0; k < runs; ++k)
                wall.push_back(time_ms([&] { result = solve(*ctx, method, mesh); }) / 1000.0);
            const double seconds = median(wall);
            seconds_of[method] = seconds;
            const passes::SphereMetrics m = passes::sphere_metrics(mesh, result.positions);
            // How many times the harmonic method's time this one took.
            char versus[32] = "";
            if (seconds_of.count("harmonic") && method != "harmonic")
                std::snprintf(versus, sizeof versus, "%.2fx", seconds / seconds_of["harmonic"]);
            std::printf("%-20s %7zu %-7s %9.3f %6zu %9.5f %8.2f %8.2f %9s %s\n", name.c_str(), mesh.vertex_count(),
                        method.c_str(), seconds, m.flips, m.conformal_ratio, m.angle_distortion_deg.mean,
                        m.angle_distortion_deg.p95, versus, result.converged ? "" : "did not converge");
            std::fflush(stdout);
            j["rows"].push_back({{"mesh", name},
                                 {"vertices", mesh.vertex_count()},
                                 {"method", method},
                                 {"seconds", seconds},
                                 {"flips", m.flips},
                                 {"conformal_energy", m.conformal_energy},
                                 {"conformal_ratio", m.conformal_ratio},
                                 {"angle_distortion_deg",
                                  {{"mean", m.angle_distortion_deg.mean},
                                   {"p95", m.angle_distortion_deg.p95},
                                   {"max", m.angle_distortion_deg.max}}},
                                 {"smallest_area", m.smallest_area},
                                 {"converged", result.converged},
                                 {"note", result.note}});
        }
    }
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

}  // namespace

void add_bench_sphere_command(CLI::App& bench, const GlobalOptions& global) {
    auto o = std::make_shared<SphereBenchOptions>();
    auto* cmd = bench.add_subcommand("sphere", "harmonic vs linear vs kanai vs gu spherical maps, time and quality");
    cmd->add_option(
        "--mesh", o->meshes,
        "Closed genus-0 meshes (default: those of ../shared/meshes and the fetched derived/armadillo_loop1, "
        "derived/bunny_loop1)");
    cmd->add_option("--method", o->methods,
                    "Methods to run (default: harmonic linear kanai gu; gpu is an alias of harmonic)")
        ->transform(CLI::Transformer(std::map<std::string, std::string>{{"gpu", "harmonic"}}))
        ->check(CLI::IsMember({"harmonic", "kanai", "gu", "linear"}));
    add_count_option(cmd, "--runs", o->runs, 1, 1000, "Runs per case; the median is reported (default 3)");
    add_count_option(cmd, "--gu-max-vertices", o->gu_max_vertices, 0, UINT32_MAX,
                     "Run gu only on meshes up to this size (default 10000)");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] { run_writing({}, {json_output(o->json)}, [&] { run_sphere_bench(*o, global); }); });
}

}  // namespace gimg::cli

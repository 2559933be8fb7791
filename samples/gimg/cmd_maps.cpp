// gimg maps MESH --levels J [--base N] [--k K] [--compress R] --out DIR [--json FILE]
// A closed mesh -> MAPS base domain -> 4-to-1 remesh levels 1..J -> k-disk wavelets (docs/maps.md).
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "maps_report.h"
#include "progress_line.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/maps.h"

#include <cstdio>

namespace gimg::cli {

namespace {

struct MapsCommandOptions {
    std::string mesh, out, json, k = "1";
    std::uint32_t levels = 4, base = 0, picture = 480, smooth = 0;
    std::uint64_t samples = 0;
    double lambda = 0.5, compress = 0.0, max_cone = 2.0;
    std::string flattening = "polar";
    bool cpu = false;
};

void run_maps(const MapsCommandOptions& o, const GlobalOptions& global) {
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    const int k = parse_wavelet_k(o.k);
    passes::MapsOptions mo;
    mo.lambda = o.lambda;
    mo.base_vertices = o.base;
    mo.flattening = o.flattening == "za" ? passes::RingFlattening::Za : passes::RingFlattening::Polar;
    mo.max_cone = o.max_cone;
    mo.smoothing = o.smooth;
    std::shared_ptr<Context> ctx = open_context(global);  // the pictures need it even with --cpu
    Context* gpu = o.cpu ? nullptr : ctx.get();
    if (!global.quiet)
        std::printf("%s: %zu vertices, %zu faces; MAPS to level %u, wavelets k = %s, on the %s\n", o.mesh.c_str(),
                    mesh.vertex_count(), mesh.face_count(), o.levels, o.k.c_str(), gpu ? "GPU" : "CPU");
    const passes::MapsRemesh r = passes::maps_remesh(gpu, mesh, mo, o.levels);
    const MapsWavelets w = maps_wavelets(gpu, r.remesh, k, o.compress);

    const std::filesystem::path dir(o.out);
    geo::save_mesh(r.domain.base, dir / "base.obj");
    for (std::uint32_t j = 1; j <= o.levels; ++j)
        geo::save_mesh(r.remesh.level_mesh(j), dir / ("remesh_" + std::to_string(j) + ".obj"));
    geo::save_mesh(w.coarse, dir / ("coarse_" + std::to_string(o.levels - 1) + ".obj"));
    if (o.compress > 0.0) geo::save_mesh(w.compressed, dir / "compressed.obj");
    write_wavelets(r.remesh, k, w.coefficients, dir / "wavelets.bin");
    write_maps_pictures(*ctx, mesh, r, w, o.picture, dir);

    geo::SurfaceDistanceOptions so;
    if (o.samples) so.sampling.sample_count = o.samples;
    ProgressLine line(global.quiet);
    const MapsErrors errors = maps_errors(mesh, r, w, so, line.on() ? &line : nullptr);
    line.finish();
    if (!global.quiet) print_maps_report(mesh, r, w, errors);
    nlohmann::json j = maps_json(mesh, r, w, errors);
    j["mesh"] = o.mesh;
    j["method"] = gpu ? "gpu" : "cpu";
    j["k"] = o.k;
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
    if (!global.quiet)
        std::printf("wrote %s/{base.obj, remesh_1..%u.obj, coarse_%u.obj, wavelets.bin, base.png, remesh.png%s}\n",
                    o.out.c_str(), o.levels, o.levels - 1, o.compress > 0.0 ? ", compressed.obj" : "");
}

}  // namespace

void add_maps_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<MapsCommandOptions>();
    auto* cmd = app.add_subcommand("maps", "Closed mesh -> MAPS base domain -> 4-to-1 remesh -> k-disk wavelets");
    cmd->add_option("mesh", o->mesh, "Input mesh: closed, manifold, oriented (any genus)")->required();
    cmd->add_option("--out", o->out, "Output folder (base.obj, remesh_J.obj, coarse_J-1.obj, wavelets.bin, pictures)")
        ->required();
    add_count_option(cmd, "--levels", o->levels, 1, 7, "Subdivision levels J of the remesh (default 4)");
    add_count_option(
        cmd, "--base", o->base, 4, 1'000'000,
        "Base domain size in vertices (default: a twentieth of the mesh's, within 50 (1 + genus) and 150 (1 + genus))");
    cmd->add_option("--k", o->k, "Wavelet: lazy, or the k-disk wavelet's k: 0, 1 (default) or 2")
        ->check(CLI::IsMember({"lazy", "0", "1", "2"}));
    add_number_option(cmd, "--lambda", o->lambda, 0.0, 1.0,
                      "Weight of the one-ring area against the curvature in the removal priority (default 0.5)");
    cmd->add_option("--flattening", o->flattening,
                    "Ring flattening radii: polar (r, default) or za (the paper's z^a, r^a; undersamples protrusions)")
        ->check(CLI::IsMember({"polar", "za"}));
    add_number_option(cmd, "--max-cone", o->max_cone, 0.0, 1e6,
                      "Keep vertices whose flattening scales angles by more than this or less than its inverse "
                      "(cone tips; default 2, 0 for none, else at least 1)");
    add_count_option(cmd, "--smooth", o->smooth, 0, 1000,
                     "Smoothing iterations of the remesh points inside base triangles (default 0: none)");
    add_number_option(cmd, "--compress", o->compress, 0.0, 1.0,
                      "Also rebuild the finest level from this fraction of the detail coefficients (compressed.obj)");
    add_count_option(cmd, "--picture", o->picture, 64, 4096,
                     "Side of each panel of the pictures in pixels (default 480)");
    cmd->add_flag("--cpu", o->cpu, "Map the remesh points and run the wavelets with the CPU twins");
    add_count_option(cmd, "--samples", o->samples, 1, 100'000'000,
                     "Surface samples per mesh for the distances (default max(1M, 10 per face))");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] {
        std::vector<std::string> names{"base.obj", "coarse_" + std::to_string(o->levels - 1) + ".obj", "wavelets.bin",
                                       "base.png", "remesh.png"};
        for (std::uint32_t j = 1; j <= o->levels; ++j) names.push_back("remesh_" + std::to_string(j) + ".obj");
        if (o->compress > 0.0) names.push_back("compressed.obj");
        auto outputs = folder_outputs("--out", o->out, names);
        outputs.push_back(json_output(o->json));
        run_writing({o->mesh}, outputs, [&] {
            make_output_folder("--out", o->out);
            run_maps(*o, global);
        });
    });
}

}  // namespace gimg::cli

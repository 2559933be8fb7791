// gimg bench gim [--mesh PATH]... [--size N]... [--samples N] [--json FILE]
//
// The thesis's table 6.1 redone: per disk mesh, every variant of the square map, Yoshizawa et al.'s
// stretch reweighting at its best iterate (by reconstruction error, as the thesis takes it) and,
// when built with CGAL, CGAL's square-border maps, each sampled into N x N geometry images,
// reconstructed and measured against the original both ways (RMS and Hausdorff relative to the
// diagonal, PSNR = 20 log10(1 / RMS)), with the map's time on the GPU and on the CPU.
#include "bench_paths.h"
#include "cgal_peer.h"
#include "command_files.h"
#include "commands.h"
#include "gim_report.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/reconstruct.h"

#include <cmath>
#include <cstdio>

namespace gimg::cli {

namespace {

struct GimBenchOptions {
    std::vector<std::string> meshes;
    std::vector<std::uint32_t> sizes{0, 65, 129, 257};  // 0: round(sqrt(V)), the thesis's choice
    std::uint64_t samples = 300000;
    std::uint64_t cgal_iterations = 15;
    bool cpu = true;
    bool select = true;
    std::string json;
};

struct Row {
    std::string method;
    std::size_t iterations = 0;  // reweighting iterations (the best one for stretch)
    double seconds = 0.0;        // the map on the GPU (ours) or CGAL's parameterize()
    double cpu_seconds = 0.0;    // ours: the same map with the CPU twin
    double solve_seconds = 0.0;  // ours: of seconds, the linear solves
    std::uint64_t submissions = 0;     // ours: the GPU map's queue submissions
    double device_wait_seconds = 0.0;  // and, of seconds, the host's time waiting for them
    std::size_t flipped = 0;
    std::vector<GimError> errors;       // per size
    std::vector<std::size_t> selected;  // "-selected" rows: the iterate returned, per size
};

void run_gim_bench(const GimBenchOptions& o, const GlobalOptions& global) {
    for (std::uint32_t n : o.sizes) passes::geometry_image_size(n, 4);  // refuses 1 before any work
    std::vector<std::string> meshes = o.meshes;
    if (meshes.empty())
        for (const char* name :
             {"mannequin_devil.off", "nefertiti.off", "mushroom.off", "three_peaks.off", "terrain.obj"})
            meshes.push_back((shared_mesh_dir() / name).string());
    auto context = open_context(global);
    Context& ctx = *context;
    geo::SurfaceDistanceOptions so;
    so.sampling.sample_count = o.samples;
    nlohmann::json out_meshes = nlohmann::json::array();
    for (const std::string& path : meshes) {
        const geo::Mesh mesh = geo::load_mesh(path);
        passes::check_disk_mesh(mesh);
        std::vector<std::uint32_t> sizes;
        for (std::uint32_t n : o.sizes) sizes.push_back(passes::geometry_image_size(n, mesh.vertex_count()));
        auto errors_of = [&](const std::vector<glm::dvec2>& uv) {
            std::vector<GimError> e;
            for (std::uint32_t n : sizes)
                e.push_back(gim_error(
                    mesh, passes::reconstruct_gpu(ctx, passes::geometry_image_gpu(ctx, mesh, uv, n), {}), so));
            return e;
        };
        std::vector<Row> rows;
        std::array<std::uint32_t, 4> corners{};
        for (auto variant : {passes::ParameterizeVariant::Tutte, passes::ParameterizeVariant::Floater,
                             passes::ParameterizeVariant::Stretch, passes::ParameterizeVariant::Density,
                             passes::ParameterizeVariant::Uniform3d, passes::ParameterizeVariant::Curvature}) {
            passes::ParameterizeOptions po;
            po.variant = variant;
            po.keep_iterates = variant == passes::ParameterizeVariant::Stretch;
            const passes::Parameterization map = passes::parameterize_square(&ctx, mesh, po);
            corners = map.boundary.corners;
            Row row{.method = passes::variant_name(variant),
                    .iterations = map.iterations.size() - 1,
                    .seconds = map.seconds,
                    .solve_seconds = map.solve_seconds,
                    .submissions = map.submissions,
                    .device_wait_seconds = map.device_wait_seconds};
            if (o.cpu) row.cpu_seconds = passes::parameterize_square(nullptr, mesh, po).seconds;
            if (variant == passes::ParameterizeVariant::Stretch) {
                // The thesis takes Yoshizawa's iterate of least shape error (per size here).
                row.errors.assign(sizes.size(), GimError{.rms = INFINITY});
                for (std::size_t t = 0; t < map.iterates.size(); ++t) {
                    const std::vector<GimError> e = errors_of(map.iterates[t]);
                    for (std::size_t k = 0; k < sizes.size(); ++k)
                        if (e[k].rms < row.errors[k].rms) row.errors[k] = e[k];
                    if (e.back().rms <= row.errors.back().rms)
                        row.iterations = t, row.flipped = map.iterations[t].flipped;
                }
            } else {
                row.flipped = passes::count_flipped(mesh, map.uv);
                row.errors = errors_of(map.uv);
            }
            rows.push_back(std::move(row));
        }
        // What --select returns: per size, the iterate whose image at that size rebuilds the mesh
        // best (the CPU twin; its seconds include the measuring of every iterate).
        if (o.select)
            for (auto variant : {passes::ParameterizeVariant::Density, passes::ParameterizeVariant::Uniform3d,
                                 passes::ParameterizeVariant::Curvature}) {
                Row row{.method = std::string(passes::variant_name(variant)) + "-selected"};
                for (std::uint32_t n : sizes) {
                    passes::ParameterizeOptions po;
                    po.variant = variant;
                    po.select_size = n;
                    const passes::Parameterization map = passes::parameterize_square(nullptr, mesh, po);
                    if (row.selected.empty()) row.cpu_seconds = map.seconds;
                    row.selected.push_back(map.selected);
                    row.iterations = map.selected;
                    row.flipped = std::max(row.flipped, passes::count_flipped(mesh, map.uv));
                    row.errors.push_back(gim_error(
                        mesh, passes::reconstruct_gpu(ctx, passes::geometry_image_gpu(ctx, mesh, map.uv, n), {}), so));
                }
                rows.push_back(std::move(row));
            }
        if (cgal_available())
            for (auto method : {CgalSquareMap::MeanValue, CgalSquareMap::DiscreteAuthalic,
                                CgalSquareMap::DiscreteConformal, CgalSquareMap::IterativeAuthalic}) {
                const CgalSquareMapResult r = cgal_square_map(mesh, corners, method, unsigned(o.cgal_iterations));
                if (!r.error.empty())
                    throw geo::InputError(path + ": " + cgal_square_map_name(method) + " failed: " + r.error);
                rows.push_back({.method = cgal_square_map_name(method),
                                .iterations = method == CgalSquareMap::IterativeAuthalic ? o.cgal_iterations : 0,
                                .seconds = r.seconds,
                                .flipped = passes::count_flipped(mesh, r.uv),
                                .errors = errors_of(r.uv)});
            }
        const std::string name = std::filesystem::path(path).filename().string();
        if (!global.quiet) {
            std::printf("\n%s: %zu vertices, %zu faces; PSNR in dB (RMS relative to the diagonal) per image size\n",
                        name.c_str(), mesh.vertex_count(), mesh.face_count());
            std::printf("%-24s %5s %9s %9s %7s", "method", "iter", "map s", "cpu s", "flipped");
            for (std::uint32_t n : sizes) std::printf(" %18s", ("N = " + std::to_string(n)).c_str());
            std::printf("\n");
            for (const Row& r : rows) {
                std::printf("%-24s %5zu %9.3f %9.3f %7zu", r.method.c_str(), r.iterations, r.seconds, r.cpu_seconds,
                            r.flipped);
                for (const GimError& e : r.errors) std::printf("   %6.2f (%.2e)", e.psnr, e.rms);
                std::printf("\n");
            }
            std::fflush(stdout);
        }
        nlohmann::json jrows = nlohmann::json::array();
        for (const Row& r : rows) {
            nlohmann::json per_size = nlohmann::json::array();
            for (std::size_t k = 0; k < sizes.size(); ++k) {
                nlohmann::json e = gim_error_json(r.errors[k]);
                e["size"] = sizes[k];
                per_size.push_back(e);
            }
            if (!r.selected.empty())
                for (std::size_t k = 0; k < sizes.size(); ++k) per_size[k]["selected_iteration"] = r.selected[k];
            jrows.push_back({{"method", r.method},
                             {"iterations", r.iterations},
                             {"seconds", r.seconds},
                             {"cpu_seconds", r.cpu_seconds},
                             {"solve_seconds", r.solve_seconds},
                             {"submissions", r.submissions},
                             {"device_wait_seconds", r.device_wait_seconds},
                             {"flipped", r.flipped},
                             {"sizes", per_size}});
        }
        out_meshes.push_back(
            {{"mesh", name}, {"vertices", mesh.vertex_count()}, {"faces", mesh.face_count()}, {"rows", jrows}});
    }
    nlohmann::json j{{"samples", o.samples}, {"cgal", cgal_available()}, {"meshes", out_meshes}};
    add_machine_figures(j, &ctx);
    write_json(o.json, j);
}

}  // namespace

void add_bench_gim_command(CLI::App& bench, const GlobalOptions& global) {
    auto o = std::make_shared<GimBenchOptions>();
    auto* cmd = bench.add_subcommand("gim",
                                     "Parameterization geometry images: every variant, Yoshizawa and CGAL "
                                     "(the thesis's table 6.1)");
    cmd->add_option("--mesh", o->meshes,
                    "Disk meshes (default: mannequin_devil, nefertiti, mushroom, three_peaks, terrain of "
                    "../shared/meshes)");
    add_count_list_option(cmd, "--size", o->sizes, 0, 16384,
                          "Image sizes N; 0 = round(sqrt(vertices)) (default 0 65 129 257)");
    add_count_option(cmd, "--samples", o->samples, 1000, 100'000'000, "Surface samples per direction (default 300000)");
    add_count_option(cmd, "--cgal-iterations", o->cgal_iterations, 1, 1000,
                     "Iterations of CGAL's iterative authalic map (default 15)");
    cmd->add_flag("!--no-cpu", o->cpu, "Skip timing the CPU twin of each map");
    cmd->add_flag("!--no-select", o->select,
                  "Skip the rows of what gim --select returns (density, uniform3d, curvature; a run per size)");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] { run_writing({}, {json_output(o->json)}, [&] { run_gim_bench(*o, global); }); });
}

}  // namespace gimg::cli

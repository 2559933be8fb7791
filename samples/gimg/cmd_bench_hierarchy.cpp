// gimg bench hierarchical [--mesh PATH]... [--size N]... [--base B] [--reach R] [--samples N] [--runs N]
//                         [--json FILE]
//
// The thesis's table 3.1 redone: per mesh and size N, the ordinary N x N cylindrical image (ray
// cast, every block connected) against the hierarchy from B x B, each reconstructed and measured
// against the original both ways (RMS in cylinder units, radius 1, as the thesis reports), with
// the wall time of each and of every level of the hierarchy (the encoders' medians over --runs,
// the CPU's and the GPU's taking turns, each timed run after an untimed one of its own).
#include "bench_paths.h"
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/passes/cylinder_hierarchy.h"
#include "gimg/passes/reconstruct.h"

#include <cstdio>
#include <limits>
#include <tuple>

namespace gimg::cli {

namespace {

struct HierarchyBenchOptions {
    std::vector<std::string> meshes;
    std::vector<std::uint32_t> sizes{64, 128, 256};
    std::uint32_t base = 32;
    double reach = passes::CylinderHierarchyOptions{}.reach;
    std::string misses = "radial";
    std::uint64_t samples = 300000;
    std::uint32_t runs = 3;
    std::string json;
};

// Element-wise medians of per-level times.
std::vector<double> level_medians(const std::vector<std::vector<double>>& runs) {
    std::vector<double> out;
    for (std::size_t k = 0; !runs.empty() && k < runs.front().size(); ++k) {
        std::vector<double> v;
        for (const auto& r : runs) v.push_back(r[k]);
        out.push_back(median(v));
    }
    return out;
}

// RMS both ways and symmetric, in cylinder units.
std::tuple<double, double, double> error_of(const geo::Mesh& original, const geo::Mesh& rebuilt, double scale,
                                            std::uint64_t samples) {
    geo::SurfaceDistanceOptions so;
    so.sampling.sample_count = samples;
    const geo::SurfaceDistance d = geo::surface_distance(original, rebuilt, so);
    return {d.a_to_b.rms * scale, d.b_to_a.rms * scale, d.symmetric.rms * scale};
}

void run_hierarchy_bench(const HierarchyBenchOptions& o, const GlobalOptions& global) {
    std::vector<std::string> meshes = o.meshes;
    if (meshes.empty())
        for (const char* name : {"armadillo", "bunny", "camel", "homer", "elephant"})
            meshes.push_back((shared_mesh_dir() / (std::string(name) + ".off")).string());
    for (std::uint32_t n : o.sizes) passes::check_hierarchy_sizes(o.base, n);
    if (!global.quiet) {
        std::printf(
            "gimg bench hierarchical: ordinary N x N ray cast (every block connected) vs hierarchy from %ux%u "
            "(reach %g, misses %s); RMS in cylinder units, original->reconstruction / reconstruction->original; times "
            "in ms (the ordinary image; the hierarchy's CPU and GPU encoders, the same hierarchy, medians of %u "
            "runs)\n",
            o.base, o.base, o.reach, o.misses.c_str(), o.runs);
        std::printf("%-14s %5s | %10s %10s %8s | %10s %10s %8s %8s | %s\n", "mesh", "N", "ord A->B", "ord B->A",
                    "ord ms", "hier A->B", "hier B->A", "cpu ms", "gpu ms",
                    "cpu/gpu ms: BVH (GPU: and upload), per level (level 1 with the BVH)");
    }
    auto context = open_context(global);
    Context& ctx = *context;
    nlohmann::json rows = nlohmann::json::array();
    for (const std::string& path : meshes) {
        const geo::Mesh mesh = geo::load_mesh(path);
        const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
        const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, frame);
        passes::ReconstructOptions off;
        off.threshold = std::numeric_limits<float>::infinity();
        for (std::uint32_t n : o.sizes) {
            geo::Mesh ordinary, hierarchical;
            passes::CylinderHierarchy h;
            passes::CylinderImage image;
            const double ord_ms = time_ms([&] {
                image = passes::cylinder_raycast(cyl, n, n);
                ordinary = passes::reconstruct_cpu(image, frame, off);
            });
            const passes::CylinderHierarchyOptions options{
                .base = o.base, .size = n, .reach = o.reach, .miss = passes::hierarchy_miss(o.misses)};
            passes::CylinderHierarchy on_gpu;
            std::vector<double> cpu_runs, gpu_runs, pass_runs, cpu_tree_runs, gpu_tree_runs;
            std::vector<std::vector<double>> cpu_levels, gpu_levels;
            // Each timed run follows an untimed one of the same encoder: on lavapipe the GPU encoder
            // run right after the CPU's took up to 1.6 times as long as after itself, the CPU's up
            // to 1.15 times. The GPU encoder's untimed run takes the timestamps (its levels and
            // passes); the timed one goes without, as lavapipe pays for them.
            passes::CylinderHierarchyOptions stamped = options;
            stamped.timestamps = true;
            for (std::uint32_t r = 0; r < o.runs; ++r) {
                h = passes::cylinder_hierarchy_cpu(cyl, options);
                cpu_runs.push_back(time_ms([&] { h = passes::cylinder_hierarchy_cpu(cyl, options); }));
                const passes::CylinderHierarchy timed = passes::cylinder_hierarchy_gpu(ctx, cyl, stamped);
                gpu_runs.push_back(time_ms([&] { on_gpu = passes::cylinder_hierarchy_gpu(ctx, cyl, options); }));
                if (on_gpu.t != h.t || on_gpu.valid != h.valid || timed.t != h.t || timed.valid != h.valid)
                    throw std::runtime_error("bench hierarchical: the GPU encoder differs from the CPU encoder");
                pass_runs.push_back(timed.gpu_ms);
                cpu_tree_runs.push_back(h.tree_ms);
                gpu_tree_runs.push_back(on_gpu.tree_ms);
                cpu_levels.push_back(h.level_ms);
                gpu_levels.push_back(timed.level_ms);
            }
            const double hier_ms = median(cpu_runs), gpu_ms = median(gpu_runs);
            const double cpu_tree_ms = median(cpu_tree_runs), gpu_tree_ms = median(gpu_tree_runs);
            const std::vector<double> cpu_level_ms = level_medians(cpu_levels),
                                      gpu_level_ms = level_medians(gpu_levels);
            const passes::HierarchyGrid grid = passes::decode_cylinder_hierarchy(h, h.levels());
            hierarchical = passes::hierarchy_mesh(grid, frame, std::numeric_limits<double>::infinity());
            const auto [oa, ob, os] = error_of(mesh, ordinary, frame.scale, o.samples);
            const auto [ha, hb, hs] = error_of(mesh, hierarchical, frame.scale, o.samples);
            // Each also as gimg reconstructs it by default: blocks across a gap cut.
            const auto [oca, ocb, ocs] =
                error_of(mesh, passes::reconstruct_cpu(image, frame, {}), frame.scale, o.samples);
            const auto [hca, hcb, hcs] = error_of(mesh, passes::hierarchy_mesh(grid, frame), frame.scale, o.samples);
            std::string levels = "tree " + std::to_string(int(cpu_tree_ms + 0.5)) + "/" +
                                 std::to_string(int(gpu_tree_ms + 0.5)) + ", levels ";
            for (std::size_t k = 0; k < cpu_level_ms.size(); ++k)
                levels += (k ? " " : "") + std::to_string(int(cpu_level_ms[k] + 0.5)) + "/" +
                          std::to_string(int(gpu_level_ms[k] + 0.5));
            const std::string name = std::filesystem::path(path).stem().string();
            if (!global.quiet)
                std::printf(
                    "%-14s %5u | %10.6f %10.6f %8.1f | %10.6f %10.6f %8.1f %8.1f | %s\n%20s | %10.6f %10.6f %8s | "
                    "%10.6f %10.6f   (cut by default thresholds; symmetric %.6f against %.6f)\n",
                    name.c_str(), n, oa, ob, ord_ms, ha, hb, hier_ms, gpu_ms, levels.c_str(), "cut", oca, ocb, "", hca,
                    hcb, hcs, ocs);
            rows.push_back({{"mesh", name},
                            {"size", n},
                            {"ordinary",
                             {{"a_to_b_rms", oa},
                              {"b_to_a_rms", ob},
                              {"symmetric_rms", os},
                              {"ms", ord_ms},
                              {"cut", {{"a_to_b_rms", oca}, {"b_to_a_rms", ocb}, {"symmetric_rms", ocs}}}}},
                            {"hierarchical",
                             {{"a_to_b_rms", ha},
                              {"symmetric_rms", hs},
                              {"b_to_a_rms", hb},
                              {"ms", hier_ms},
                              {"level_ms", cpu_level_ms},
                              {"tree_ms", cpu_tree_ms},
                              {"gpu_tree_ms", gpu_tree_ms},
                              {"gpu_ms", gpu_ms},
                              {"gpu_over_cpu", gpu_ms / hier_ms},
                              {"gpu_pass_ms", median(pass_runs)},
                              {"gpu_level_ms", gpu_level_ms},
                              {"cut", {{"a_to_b_rms", hca}, {"b_to_a_rms", hcb}, {"symmetric_rms", hcs}}}}}});
        }
    }
    nlohmann::json j{{"base", o.base},       {"reach", o.reach}, {"misses", o.misses},
                     {"samples", o.samples}, {"runs", o.runs},   {"rows", rows}};
    add_machine_figures(j, &ctx);
    write_json(o.json, j);
}

}  // namespace

void add_bench_hierarchy_command(CLI::App& bench, const GlobalOptions& global) {
    auto o = std::make_shared<HierarchyBenchOptions>();
    auto* cmd =
        bench.add_subcommand("hierarchical", "Ordinary vs hierarchical cylindrical images (the thesis's table 3.1)");
    cmd->add_option("--mesh", o->meshes,
                    "Meshes (default: armadillo, bunny, camel, homer, elephant of ../shared/meshes)");
    add_count_list_option(cmd, "--size", o->sizes, 2, 16384, "Final sizes N (default 64 128 256)");
    add_count_option(cmd, "--base", o->base, 2, 8192, "Level 1 is B x B (default 32)");
    add_number_option(cmd, "--reach", o->reach, 0.0, 1e6, "Ray reach in parent spans (0: without limit; default 8)");
    cmd->add_option("--misses", o->misses,
                    "A ray that finds nothing within reach gives way to the ordinary image's ray (radial, default), "
                    "leaves a sample on the interpolated surface (surface) or a hole (empty)")
        ->check(CLI::IsMember({"surface", "empty", "radial"}));
    add_count_option(cmd, "--samples", o->samples, 1000, 100'000'000, "Surface samples per direction (default 300000)");
    add_count_option(cmd, "--runs", o->runs, 1, 1000,
                     "Timed encoder runs, CPU and GPU taking turns, each after an untimed one; medians (default 3)");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] { run_writing({}, {json_output(o->json)}, [&] { run_hierarchy_bench(*o, global); }); });
}

}  // namespace gimg::cli

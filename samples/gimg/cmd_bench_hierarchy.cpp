// gimg bench hierarchical [--mesh PATH]... [--size N]... [--base B] [--reach R] [--samples N] [--runs N]
//                         [--processes P] [--json FILE]
//
// The thesis's table 3.1 redone: per mesh and size N, the ordinary N x N cylindrical image (ray
// cast, every block connected) against the hierarchy from B x B, each reconstructed and measured
// against the original both ways (RMS in cylinder units, radius 1, as the thesis reports), with
// the wall time of each and of every level of the hierarchy (the encoders' medians over --runs,
// the CPU's and the GPU's taking turns, each timed run after an untimed one of its own). With
// --processes, the whole bench runs in P processes one after another and the times are the medians
// of their medians: how fast an encoder's BVH build runs differs from one process to the next.
#include "bench_paths.h"
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "self_process.h"
#include "timing.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/passes/cylinder_hierarchy.h"
#include "gimg/passes/reconstruct.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
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
    std::uint32_t processes = 1;
    std::string json;
};

// The figures of a row that are times, which differ between processes; the rest must not.
const char* const kOrdinaryTimes[] = {"ms"};
const char* const kHierarchyTimes[] = {"ms",     "level_ms",     "tree_ms",     "gpu_tree_ms",
                                       "gpu_ms", "gpu_over_cpu", "gpu_pass_ms", "gpu_level_ms"};

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

std::vector<std::string> bench_meshes(const HierarchyBenchOptions& o) {
    std::vector<std::string> meshes = o.meshes;
    if (meshes.empty())
        for (const char* name : {"armadillo", "bunny", "camel", "homer", "elephant"})
            meshes.push_back((shared_mesh_dir() / (std::string(name) + ".off")).string());
    return meshes;
}

void print_header(const HierarchyBenchOptions& o) {
    const std::string medians = "medians of " + std::to_string(o.runs) + " runs" +
                                (o.processes > 1 ? ", then over " + std::to_string(o.processes) + " processes" : "");
    std::printf(
        "gimg bench hierarchical: ordinary N x N ray cast (every block connected) vs hierarchy from %ux%u "
        "(reach %g, misses %s); RMS in cylinder units, original->reconstruction / reconstruction->original; times "
        "in ms (the ordinary image; the hierarchy's CPU and GPU encoders, the same hierarchy, %s)\n",
        o.base, o.base, o.reach, o.misses.c_str(), medians.c_str());
    std::printf("%-14s %5s | %10s %10s %8s | %10s %10s %8s %8s | %s\n", "mesh", "N", "ord A->B", "ord B->A", "ord ms",
                "hier A->B", "hier B->A", "cpu ms", "gpu ms",
                "cpu/gpu ms: BVH (GPU: and upload), per level (level 1 with the BVH)");
}

void print_row(const nlohmann::json& row) {
    const nlohmann::json &ord = row["ordinary"], &hier = row["hierarchical"];
    auto rounded = [](const nlohmann::json& ms) { return std::to_string(int(ms.get<double>() + 0.5)); };
    std::string levels = "tree " + rounded(hier["tree_ms"]) + "/" + rounded(hier["gpu_tree_ms"]) + ", levels ";
    for (std::size_t k = 0; k < hier["level_ms"].size(); ++k)
        levels += (k ? " " : "") + rounded(hier["level_ms"][k]) + "/" + rounded(hier["gpu_level_ms"][k]);
    const std::string name = row["mesh"];
    std::printf(
        "%-14s %5u | %10.6f %10.6f %8.1f | %10.6f %10.6f %8.1f %8.1f | %s\n%20s | %10.6f %10.6f %8s | "
        "%10.6f %10.6f   (cut by default thresholds; symmetric %.6f against %.6f)\n",
        name.c_str(), row["size"].get<unsigned>(), ord["a_to_b_rms"].get<double>(), ord["b_to_a_rms"].get<double>(),
        ord["ms"].get<double>(), hier["a_to_b_rms"].get<double>(), hier["b_to_a_rms"].get<double>(),
        hier["ms"].get<double>(), hier["gpu_ms"].get<double>(), levels.c_str(), "cut",
        ord["cut"]["a_to_b_rms"].get<double>(), ord["cut"]["b_to_a_rms"].get<double>(), "",
        hier["cut"]["a_to_b_rms"].get<double>(), hier["cut"]["b_to_a_rms"].get<double>(),
        hier["cut"]["symmetric_rms"].get<double>(), ord["cut"]["symmetric_rms"].get<double>());
    if (hier.contains("gpu_over_cpu_by_process")) {
        std::printf("%20s | GPU over CPU encoder, process by process:", "");
        for (const auto& r : hier["gpu_over_cpu_by_process"]) std::printf(" %.2f", r.get<double>());
        std::printf(" (median %.2f)\n", hier["gpu_over_cpu"].get<double>());
    }
}

// The whole bench in this process: the JSON it writes, each row printed as it is measured.
nlohmann::json measure(const HierarchyBenchOptions& o, const GlobalOptions& global) {
    const std::vector<std::string> meshes = bench_meshes(o);
    for (std::uint32_t n : o.sizes) passes::check_hierarchy_sizes(o.base, n);
    if (!global.quiet) print_header(o);
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
            // The first GPU run creates the pipelines, which no run's figures should hold.
            if (rows.empty()) passes::cylinder_hierarchy_gpu(ctx, cyl, options);
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
            const passes::HierarchyGrid grid = passes::decode_cylinder_hierarchy(h, h.levels());
            hierarchical = passes::hierarchy_mesh(grid, frame, std::numeric_limits<double>::infinity());
            const auto [oa, ob, os] = error_of(mesh, ordinary, frame.scale, o.samples);
            const auto [ha, hb, hs] = error_of(mesh, hierarchical, frame.scale, o.samples);
            // Each also as gimg reconstructs it by default: blocks across a gap cut.
            const auto [oca, ocb, ocs] =
                error_of(mesh, passes::reconstruct_cpu(image, frame, {}), frame.scale, o.samples);
            const auto [hca, hcb, hcs] = error_of(mesh, passes::hierarchy_mesh(grid, frame), frame.scale, o.samples);
            rows.push_back({{"mesh", std::filesystem::path(path).stem().string()},
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
                              {"level_ms", level_medians(cpu_levels)},
                              {"tree_ms", median(cpu_tree_runs)},
                              {"gpu_tree_ms", median(gpu_tree_runs)},
                              {"gpu_ms", gpu_ms},
                              {"gpu_over_cpu", gpu_ms / hier_ms},
                              {"gpu_pass_ms", median(pass_runs)},
                              {"gpu_level_ms", level_medians(gpu_levels)},
                              {"cut", {{"a_to_b_rms", hca}, {"b_to_a_rms", hcb}, {"symmetric_rms", hcs}}}}}});
            if (!global.quiet) print_row(rows.back());
        }
    }
    nlohmann::json j{{"base", o.base},       {"reach", o.reach}, {"misses", o.misses},
                     {"samples", o.samples}, {"runs", o.runs},   {"rows", rows}};
    add_machine_figures(j, &ctx);
    return j;
}

// A row without its times: what every process must measure alike.
nlohmann::json without_times(nlohmann::json row) {
    for (const char* key : kOrdinaryTimes) row["ordinary"].erase(key);
    for (const char* key : kHierarchyTimes) row["hierarchical"].erase(key);
    return row;
}

// Median over the processes of one time, or element-wise of a list of times (per level).
nlohmann::json median_over(const std::vector<nlohmann::json>& runs, std::size_t row, const char* part,
                           const char* key) {
    const nlohmann::json& first = runs.front()["rows"][row][part][key];
    auto median_at = [&](auto&& value_of) {
        std::vector<double> v;
        for (const nlohmann::json& run : runs) v.push_back(value_of(run["rows"][row][part][key]));
        return median(v);
    };
    if (!first.is_array()) return median_at([](const nlohmann::json& x) { return x.get<double>(); });
    nlohmann::json out = nlohmann::json::array();
    for (std::size_t k = 0; k < first.size(); ++k)
        out.push_back(median_at([k](const nlohmann::json& x) { return x[k].get<double>(); }));
    return out;
}

// The processes' runs as one: the first run's figures, each time the median of the runs' medians,
// and the GPU encoder's time over the CPU encoder's of each run.
nlohmann::json combine_processes(const std::vector<nlohmann::json>& runs) {
    nlohmann::json j = runs.front();
    for (std::size_t i = 0; i < j["rows"].size(); ++i) {
        for (std::size_t p = 1; p < runs.size(); ++p)
            if (without_times(runs[p]["rows"][i]) != without_times(j["rows"][i]))
                throw std::runtime_error("bench hierarchical: processes 1 and " + std::to_string(p + 1) + " measured " +
                                         j["rows"][i]["mesh"].get<std::string>() +
                                         " differently, where every process must measure the same hierarchy");
        nlohmann::json& row = j["rows"][i];
        for (const char* key : kOrdinaryTimes) row["ordinary"][key] = median_over(runs, i, "ordinary", key);
        for (const char* key : kHierarchyTimes) row["hierarchical"][key] = median_over(runs, i, "hierarchical", key);
        nlohmann::json ratios = nlohmann::json::array();
        for (const nlohmann::json& run : runs) ratios.push_back(run["rows"][i]["hierarchical"]["gpu_over_cpu"]);
        row["hierarchical"]["gpu_over_cpu_by_process"] = ratios;
    }
    j["processes"] = runs.size();
    return j;
}

// The bench once per process, one process after another, each writing its JSON into a scratch
// folder this removes.
nlohmann::json measure_in_processes(const HierarchyBenchOptions& o, const GlobalOptions& global) {
    const std::vector<std::string> meshes = bench_meshes(o);
    for (std::uint32_t n : o.sizes) passes::check_hierarchy_sizes(o.base, n);
    for (const std::string& path : meshes) geo::load_mesh(path);  // a bad mesh fails here, once
    std::error_code ec;
    std::string scratch = (std::filesystem::temp_directory_path(ec) / "gimg-bench-XXXXXX").string();
    if (ec || !mkdtemp(scratch.data())) throw std::runtime_error("bench hierarchical: no scratch folder for its runs");
    struct Remove {
        std::filesystem::path dir;
        ~Remove() {
            std::error_code e;
            std::filesystem::remove_all(dir, e);
        }
    } remove{scratch};
    auto text = [](double x) {
        std::ostringstream s;
        s.precision(17);
        s << x;
        return s.str();
    };
    std::vector<std::string> args{"--quiet", "bench", "hierarchical", "--mesh"};
    args.insert(args.end(), meshes.begin(), meshes.end());
    args.push_back("--size");
    for (std::uint32_t n : o.sizes) args.push_back(std::to_string(n));
    for (const auto& [option, value] : {std::pair<const char*, std::string>{"--base", std::to_string(o.base)},
                                        {"--reach", text(o.reach)},
                                        {"--misses", o.misses},
                                        {"--samples", std::to_string(o.samples)},
                                        {"--runs", std::to_string(o.runs)}})
        args.insert(args.end(), {option, value});
    if (!global.quiet) print_header(o);
    std::vector<nlohmann::json> runs;
    for (std::uint32_t p = 0; p < o.processes; ++p) {
        const std::filesystem::path json = std::filesystem::path(scratch) / ("run" + std::to_string(p) + ".json");
        std::vector<std::string> run_args = args;
        run_args.insert(run_args.end(), {"--json", json.string()});
        if (const int code = run_gimg(run_args); code != 0)
            throw std::runtime_error("bench hierarchical: its run in process " + std::to_string(p + 1) + " of " +
                                     std::to_string(o.processes) + " failed (exit code " + std::to_string(code) + ")");
        std::ifstream in(json);
        runs.push_back(nlohmann::json::parse(in));
    }
    nlohmann::json j = combine_processes(runs);
    if (!global.quiet)
        for (const nlohmann::json& row : j["rows"]) print_row(row);
    return j;
}

void run_hierarchy_bench(const HierarchyBenchOptions& o, const GlobalOptions& global) {
    write_json(o.json, o.processes > 1 ? measure_in_processes(o, global) : measure(o, global));
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
    add_count_option(cmd, "--processes", o->processes, 1, 100,
                     "Run the bench in P processes, one after another; times are the medians of their medians "
                     "(default 1)");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] { run_writing({}, {json_output(o->json)}, [&] { run_hierarchy_bench(*o, global); }); });
}

}  // namespace gimg::cli

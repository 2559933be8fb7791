// gimg bench quadmap [--region MESH:SIDE|MESH:A,B,C,D]... [--runs N] [--json FILE]
//
// Kuriyama & Kaneko's table 1 redone: per region (a square of SIDE times the diagonal around the
// mesh's flattest vertex, or four given corners), the relaxation's sweeps for u and v from the flat
// start and from the accelerated start, with times; the same system by BiCGSTAB (GPU and CPU twin)
// and SparseLU; CGAL's mean-value map of the same region (when built with CGAL); and the interactive
// editor's time per corner move (relaxation on the CPU twin and on the device) and per offset change. Medians of --runs runs. The whole map (cut and map_quad_region)
// is timed from the paper's accelerated start ("paper") and from the over-relaxed start ("total",
// against CGAL); both relaxations' maps are checked: flipped triangles and the largest distance from
// SparseLU's map (the paper's stopping rule sees corrections, not errors).
#include "bench_paths.h"
#include "cgal_peer.h"
#include "command_files.h"
#include "commands.h"
#include "corner_option.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/quad_region.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdio>
#include <optional>

namespace gimg::cli {

namespace {

struct QuadBenchOptions {
    std::vector<std::string> regions;
    std::uint64_t runs = 5;
    std::string json;
};

void run_quad_bench(const QuadBenchOptions& o, const GlobalOptions& global) {
    std::vector<std::string> regions = o.regions;
    if (regions.empty())
        for (const char* r : {"bunny.off:0.25", "mannequin_devil.off:0.6", "bunny.off:0.35", "bunny.off:0.45",
                              "camel.off:0.25", "bunny.off:0.65", "bunny.off:9955,8759,18272,3733"})
            regions.push_back((shared_mesh_dir() / r).string());
    auto context = open_context(global);
    Context& ctx = *context;
    if (!global.quiet)
        std::printf(
            "gimg bench quadmap: sweeps (u, v) of the relaxation (k = 0.05, tau = 1e-4); times in ms, medians "
            "of %llu\n%-22s %6s | %7s %7s | %13s %8s | %13s %6s %8s %5s %7s %8s | %6s %7s %6s %5s %7s | %8s %8s %7s | "
            "%8s | %8s %8s %8s | %7s %7s %7s\n",
            static_cast<unsigned long long>(o.runs), "region", "V", "prepare", "cut", "flat sweeps", "ms",
            "accel sweeps", "start", "ms", "flips", "vs LU", "gpu ms", "over", "sweeps", "ms", "flips", "vs LU",
            "gpu kry", "cpu kry", "direct", "cgal mv", "paper", "total", "vs cgal", "corner", "offsets", "dev crn");
    nlohmann::json rows = nlohmann::json::array();
    for (const std::string& spec : regions) {
        const auto colon = spec.rfind(':');
        if (colon == std::string::npos)
            throw geo::InputError("--region takes MESH:SIDE or MESH:A,B,C,D, got '" + spec + "'");
        const std::string path = spec.substr(0, colon), shape = spec.substr(colon + 1);
        const geo::Mesh mesh = geo::load_mesh(path);
        const std::vector<std::uint32_t> given = parse_corners(
            shape.find(',') == std::string::npos ? "auto:" + shape : shape, passes::QuadRegionCutter(mesh));
        if (given.size() != 4) throw geo::InputError("--region " + spec + ": a quad region takes four corners");
        const std::array<std::uint32_t, 4> corners{given[0], given[1], given[2], given[3]};
        passes::QuadRegion region;
        std::vector<double> prepare_ms, cut_ms, flat_ms, fast_ms, relax_gpu_ms, start_ms, over_start_ms, over_ms,
            gpu_ms, cpu_ms, direct_ms, paper_total_ms, total_ms, cgal_ms;
        passes::QuadMap flat, fast, over, gpu, exact;
        for (std::uint64_t r = 0; r < o.runs; ++r) {
            // The mesh's adjacency, normals and face-across table (once per mesh, kept by an editor),
            // then the cut itself.
            std::optional<passes::QuadRegionCutter> cutter;
            prepare_ms.push_back(time_ms([&] { cutter.emplace(mesh); }));
            cut_ms.push_back(time_ms([&] { region = cutter->cut(corners, false); }));
            flat = passes::map_quad_region(nullptr, region,
                                           {.start = passes::QuadStart::Flat, .solver = passes::QuadSolver::Iterate});
            flat_ms.push_back(flat.solve_ms);
            // Whole maps: the cut and every step of map_quad_region (adjacency, boundary, weights,
            // start, relaxation, flip count).
            paper_total_ms.push_back(
                cut_ms.back() + time_ms([&] {
                    fast = passes::map_quad_region(
                        nullptr, region, {.start = passes::QuadStart::Dijkstra, .solver = passes::QuadSolver::Iterate});
                }));
            fast_ms.push_back(fast.solve_ms);
            start_ms.push_back(fast.start_ms);
            total_ms.push_back(cut_ms.back() + time_ms([&] {
                                   over = passes::map_quad_region(nullptr, region,
                                                                  {.start = passes::QuadStart::Overrelaxed,
                                                                   .solver = passes::QuadSolver::Iterate});
                               }));
            over_start_ms.push_back(over.start_ms);
            over_ms.push_back(over.solve_ms);
            relax_gpu_ms.push_back(
                passes::map_quad_region(&ctx, region,
                                        {.start = passes::QuadStart::Dijkstra, .solver = passes::QuadSolver::Iterate})
                    .solve_ms);
            gpu = passes::map_quad_region(&ctx, region, {.solver = passes::QuadSolver::Krylov});
            gpu_ms.push_back(gpu.solve_ms);
            cpu_ms.push_back(passes::map_quad_region(nullptr, region, {.solver = passes::QuadSolver::Krylov}).solve_ms);
            exact = passes::map_quad_region(nullptr, region, {.solver = passes::QuadSolver::Direct});
            direct_ms.push_back(exact.solve_ms);
            if (cgal_available()) {
                const CgalSquareMapResult c = cgal_square_map(region.mesh, region.corners, CgalSquareMap::MeanValue);
                if (!c.error.empty()) throw geo::InputError(path + ": CGAL's mean-value map failed: " + c.error);
                cgal_ms.push_back(1000.0 * c.seconds);
            }
        }
        // The editor: a corner moved to a neighbour and back, and new offsets.
        passes::QuadRegionEditor editor(nullptr, mesh, corners, {.solver = passes::QuadSolver::Iterate});
        const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
        std::vector<double> corner_ms, offset_ms;
        passes::OffsetLattice lattice;
        lattice.offsets.assign(64, glm::dvec3(0.0));
        for (std::uint64_t r = 0; r < o.runs; ++r) {
            const std::uint32_t moved = adj.neighbors(corners[2]).front();
            corner_ms.push_back(time_ms([&] { editor.move_corner(2, r % 2 ? corners[2] : moved); }));
            lattice.offsets[27] = glm::dvec3(0.0, 0.0, 0.01 * double(r + 1) * mesh.bounds().diagonal());
            offset_ms.push_back(time_ms([&] { editor.set_lattice(lattice); }));
        }
        // The same corner moves with the relaxation on the device (the real-GPU goal).
        passes::QuadRegionEditor device_editor(&ctx, mesh, corners, {.solver = passes::QuadSolver::Iterate});
        std::vector<double> corner_gpu_ms;
        for (std::uint64_t r = 0; r < o.runs; ++r) {
            const std::uint32_t moved = adj.neighbors(corners[2]).front();
            corner_gpu_ms.push_back(time_ms([&] { device_editor.move_corner(2, r % 2 ? corners[2] : moved); }));
        }
        // The relaxation's largest distance from SparseLU's map, from either start.
        const auto from_direct = [&](const passes::QuadMap& m) {
            double d = 0.0;
            for (std::size_t i = 0; i < m.uv.size(); ++i) d = std::max(d, glm::distance(m.uv[i], exact.uv[i]));
            return d;
        };
        const double error = from_direct(fast), over_error = from_direct(over);
        const std::string name = std::filesystem::path(path).stem().string() + " (" + spec.substr(colon + 1) + ")";
        const double cgal = cgal_ms.empty() ? 0.0 : median(cgal_ms);
        if (!global.quiet) {
            std::printf(
                "%-22s %6zu | %7.1f %7.1f | %6zu %6zu %8.1f | %6zu %6zu %6.1f %8.1f %5zu %7.1e %8.1f | %6.1f %3zu %3zu "
                "%6.1f %5zu %7.1e | %8.1f %8.1f %7.1f | %8.1f | %8.1f %8.1f %8.2f | %7.1f %7.2f %7.1f\n",
                name.c_str(), region.mesh.vertex_count(), median(prepare_ms), median(cut_ms), flat.iterations_u,
                flat.iterations_v, median(flat_ms), fast.iterations_u, fast.iterations_v, median(start_ms),
                median(fast_ms), fast.flipped, error, median(relax_gpu_ms), median(over_start_ms), over.iterations_u,
                over.iterations_v, median(over_ms), over.flipped, over_error, median(gpu_ms), median(cpu_ms),
                median(direct_ms), cgal, median(paper_total_ms), median(total_ms),
                cgal > 0.0 ? cgal / median(total_ms) : 0.0, median(corner_ms), median(offset_ms),
                median(corner_gpu_ms));
            std::fflush(stdout);
        }
        rows.push_back({{"mesh", path},
                        {"side", shape.find(',') == std::string::npos ? nlohmann::json(std::stod(shape))
                                                                      : nlohmann::json(nullptr)},
                        {"corners", corners},
                        {"region_vertices", region.mesh.vertex_count()},
                        {"prepare_ms", median(prepare_ms)},
                        {"cut_ms", median(cut_ms)},
                        {"flat",
                         {{"iterations_u", flat.iterations_u},
                          {"iterations_v", flat.iterations_v},
                          {"solve_ms", median(flat_ms)}}},
                        {"accelerated",
                         {{"iterations_u", fast.iterations_u},
                          {"iterations_v", fast.iterations_v},
                          {"start_ms", median(start_ms)},
                          {"solve_ms", median(fast_ms)},
                          {"flipped", fast.flipped},
                          {"max_distance_from_direct", error},
                          {"solve_gpu_ms", median(relax_gpu_ms)},
                          {"total_ms", median(paper_total_ms)}}},
                        {"overrelaxed",
                         {{"sweeps", over.overrelaxed_sweeps},
                          {"iterations_u", over.iterations_u},
                          {"iterations_v", over.iterations_v},
                          {"start_ms", median(over_start_ms)},
                          {"solve_ms", median(over_ms)},
                          {"flipped", over.flipped},
                          {"max_distance_from_direct", over_error}}},
                        {"krylov_gpu_ms", median(gpu_ms)},
                        {"krylov_gpu_iterations", gpu.iterations_u},
                        {"krylov_cpu_ms", median(cpu_ms)},
                        {"direct_ms", median(direct_ms)},
                        {"cgal_mean_value_ms", cgal_ms.empty() ? nlohmann::json(nullptr) : nlohmann::json(cgal)},
                        {"total_ms", median(total_ms)},
                        {"corner_edit_ms", median(corner_ms)},
                        {"corner_edit_device_ms", median(corner_gpu_ms)},
                        {"offset_edit_ms", median(offset_ms)}});
    }
    nlohmann::json j{{"runs", o.runs}, {"rows", rows}};
    add_machine_figures(j, &ctx);
    write_json(o.json, j);
}

}  // namespace

void add_bench_quadmap_command(CLI::App& bench, const GlobalOptions& global) {
    auto o = std::make_shared<QuadBenchOptions>();
    auto* cmd = bench.add_subcommand("quadmap",
                                     "Quad-region maps: flat and accelerated starts, solvers, CGAL, edits "
                                     "(Kuriyama & Kaneko's table 1)");
    cmd->add_option("--region", o->regions,
                    "MESH:SIDE, a square of SIDE times the diagonal around the flattest vertex, or MESH:A,B,C,D, four "
                    "corner vertices (default: bunny at 0.25, 0.35, 0.45, 0.65; mannequin_devil at 0.6; camel at 0.25; "
                    "bunny's 11,333-vertex region 9955,8759,18272,3733)");
    add_count_option(cmd, "--runs", o->runs, 1, 1000, "Runs per case; medians (default 5)");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] { run_writing({}, {json_output(o->json)}, [&] { run_quad_bench(*o, global); }); });
}

}  // namespace gimg::cli

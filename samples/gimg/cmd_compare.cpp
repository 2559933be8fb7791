// gimg compare A B: Metro-style surface distance between two meshes (DESIGN.md, "Metrics"), each
// way and symmetric, in absolute units and relative to A's bounding-box diagonal.
#include "command_files.h"
#include "commands.h"
#include "json_output.h"
#include "progress_line.h"

#include "gimg/geometry/io.h"
#include "gimg/geometry/surface_distance.h"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

namespace gimg::cli {

namespace {

struct CompareOptions {
    std::string a;
    std::string b;
    std::string json;
    std::uint64_t samples = 0;  // 0: max(1M, 10 per face), per surface
    std::uint64_t seed = geo::SurfaceSamplingOptions{}.seed;
};

nlohmann::json stats_json(const geo::DistanceStats& s) { return {{"mean", s.mean}, {"rms", s.rms}, {"max", s.max}}; }

void print_row(const char* label, const geo::DistanceStats& abs, const geo::DistanceStats& rel) {
    std::printf("%-10s %12.6g %12.6g %12.6g   %12.6g %12.6g %12.6g\n", label, abs.mean, abs.rms, abs.max, rel.mean,
                rel.rms, rel.max);
}

void run_compare(const CompareOptions& o, const GlobalOptions& global) {
    const auto start = std::chrono::steady_clock::now();
    const geo::Mesh a = geo::load_mesh(o.a);
    const geo::Mesh b = geo::load_mesh(o.b);
    if (global.verbose)
        std::fprintf(stderr, "gimg compare: A %zu vertices, %zu faces; B %zu vertices, %zu faces\n", a.vertex_count(),
                     a.face_count(), b.vertex_count(), b.face_count());

    geo::SurfaceDistanceOptions options;
    options.sampling.sample_count = o.samples;
    options.sampling.seed = o.seed;
    const auto measure_start = std::chrono::steady_clock::now();
    ProgressLine line(global.quiet);
    if (line.on()) options.progress = [&line](double done) { line.percent("surface distance", done); };
    const geo::SurfaceDistance d = geo::surface_distance(a, b, options);
    line.finish();
    const auto end = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(end - start).count();
    const double distance_seconds = std::chrono::duration<double>(end - measure_start).count();

    if (!global.quiet) {
        std::printf("A: %s (%zu faces)\nB: %s (%zu faces)\n", o.a.c_str(), a.face_count(), o.b.c_str(), b.face_count());
        std::printf("bounding-box diagonal of A: %.6g; samples: %zu on A, %zu on B\n", d.bbox_diagonal,
                    d.a_to_b.samples, d.b_to_a.samples);
        std::printf("%-10s %12s %12s %12s   %12s %12s %12s\n", "", "mean", "rms", "max", "mean/diag", "rms/diag",
                    "max/diag");
        print_row("A -> B", d.a_to_b, d.relative(d.a_to_b));
        print_row("B -> A", d.b_to_a, d.relative(d.b_to_a));
        print_row("symmetric", d.symmetric, d.relative(d.symmetric));
        std::printf("%.3f s (distance %.3f s)\n", seconds, distance_seconds);
    }

    nlohmann::json j;
    j["a"] = o.a;
    j["b"] = o.b;
    j["a_to_b"] = stats_json(d.a_to_b);
    j["b_to_a"] = stats_json(d.b_to_a);
    j["symmetric"] = stats_json(d.symmetric);
    j["bbox_diagonal"] = d.bbox_diagonal;
    j["a_to_b_relative"] = stats_json(d.relative(d.a_to_b));
    j["b_to_a_relative"] = stats_json(d.relative(d.b_to_a));
    j["symmetric_relative"] = stats_json(d.relative(d.symmetric));
    j["samples_a"] = d.a_to_b.samples;
    j["samples_b"] = d.b_to_a.samples;
    j["seed"] = o.seed;
    j["faces_a"] = a.face_count();
    j["faces_b"] = b.face_count();
    j["seconds"] = seconds;
    j["distance_seconds"] = distance_seconds;
    j["peak_rss_mb"] = peak_rss_mb();
    write_json(o.json, j);
}

}  // namespace

void add_compare_command(CLI::App& app, const GlobalOptions& global) {
    auto options = std::make_shared<CompareOptions>();
    CLI::App* cmd =
        app.add_subcommand("compare",
                           "Surface distance between meshes A and B (Metro-style: mean, RMS and max each way "
                           "and symmetric, absolute and relative to A's bounding-box diagonal)");
    cmd->add_option("a", options->a, "Reference mesh A")->required();
    cmd->add_option("b", options->b, "Mesh B")->required();
    cmd->add_option("--json", options->json, "Also write the figures to this JSON file");
    add_count_option(cmd, "--samples", options->samples, 1, 100'000'000,
                     "Area samples per surface (default: the larger of 1,000,000 and 10 per face)");
    add_count_option(cmd, "--seed", options->seed, 0, UINT64_MAX, "Seed of the stratified sampling (fixed by default)");
    cmd->callback([options, &global] {
        run_writing({options->a, options->b}, {json_output(options->json)}, [&] { run_compare(*options, global); });
    });
}

}  // namespace gimg::cli

// gimg bench maps [--mesh PATH]... [--levels J] [--wavelet-mesh PATH]... [--time-mesh PATH] [--runs N]
//
// MAPS on every closed shared mesh: hierarchy levels, base size, the remesh error per level (RMS and
// Hausdorff, relative to the diagonal) beside a quadric decimation of the original to the same vertex
// count, stage times, and every failure; the wavelets' error against the share of details kept for
// lazy and k = 0, 1, 2; and the whole pipeline's time on one mesh, GPU passes against CPU twins.
#include "bench_paths.h"
#include "command_files.h"
#include "commands.h"
#include "decimation_peer.h"
#include "gpu_context.h"
#include "json_output.h"
#include "maps_report.h"
#include "timing.h"

#include "gimg/engine/upload.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/maps.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <tuple>

namespace gimg::cli {

namespace {

struct MapsBenchOptions {
    std::vector<std::string> meshes, wavelet_meshes;
    std::string time_mesh, json;
    std::uint32_t levels = 5;
    std::uint64_t runs = 3, samples = 300000;
};

const char* const kClosedMeshes[] = {
    "hand.off",    "bunny_small.obj", "blobby.off",       "triceratops.off",  "cow.off",     "dino.off",  "homer.off",
    "fandisk.off", "camel.off",       "armadillo.off",    "bunny.off",        "eight.off",   "elk.off",   "knot1.off",
    "femur.off",   "elephant.off",    "anchor_dense.off", "couplingdown.off", "turbine.off", "cheese.off"};

std::vector<std::string> or_defaults(const std::vector<std::string>& given, std::initializer_list<const char*> names) {
    if (!given.empty()) return given;
    std::vector<std::string> out;
    for (const char* n : names) out.push_back((shared_mesh_dir() / n).string());
    return out;
}

long long genus_of(const geo::Mesh& m) {
    long long g = 0;
    for (const auto& c : geo::analyze_topology(m).component_info) g += c.genus.value_or(0);
    return g;
}

double relative(const geo::SurfaceDistance& d, bool max) {
    const geo::DistanceStats s = d.relative(d.symmetric);
    return max ? s.max : s.rms;
}

nlohmann::json mesh_row(Context& ctx, const std::string& path, const MapsBenchOptions& o, bool quiet) {
    const std::string name = std::filesystem::path(path).filename().string();
    nlohmann::json row{{"mesh", name}};
    try {
        const geo::Mesh mesh = geo::load_mesh(path);
        row["vertices"] = mesh.vertex_count();
        row["genus"] = genus_of(mesh);
        passes::MapsRemesh r;
        const double total_ms = time_ms([&] { r = passes::maps_remesh(&ctx, mesh, {}, o.levels); });
        bool finite = true;
        for (const glm::dvec3& p : r.remesh.positions) finite = finite && std::isfinite(p.x + p.y + p.z);
        if (!finite) throw std::runtime_error("a remesh point is not finite");
        geo::SurfaceDistanceOptions so;
        so.sampling.sample_count = o.samples;
        nlohmann::json levels = nlohmann::json::array();
        for (std::uint32_t j = 1; j <= o.levels; ++j) {
            const geo::SurfaceDistance d = geo::surface_distance(mesh, r.remesh.level_mesh(j), so);
            nlohmann::json l{{"level", j},
                             {"vertices", r.remesh.vertex_count[j]},
                             {"rms", relative(d, false)},
                             {"hausdorff", relative(d, true)}};
            if (r.remesh.vertex_count[j] < mesh.vertex_count()) {
                const geo::SurfaceDistance q =
                    geo::surface_distance(mesh, quadric_decimation(mesh, r.remesh.vertex_count[j]), so);
                l["quadric_rms"] = relative(q, false);
                l["quadric_hausdorff"] = relative(q, true);
            }
            levels.push_back(l);
        }
        std::size_t refused = 0;
        for (const auto& l : r.domain.levels) refused += l.skipped;
        row.update({{"status", "ok"},
                    {"hierarchy_levels", r.domain.levels.size()},
                    {"base_vertices", r.domain.base.vertex_count()},
                    {"refused", refused},
                    {"straddling", r.map.straddling},
                    {"unplaced", r.map.unplaced},
                    {"fallbacks", r.fallbacks},
                    {"levels", levels},
                    {"seconds",
                     {{"base_domain", r.base_seconds},
                      {"subdivide", r.subdivide_seconds},
                      {"point_location", r.locate_seconds},
                      {"evaluate_gpu", r.evaluate_seconds},
                      {"total", total_ms / 1e3}}}});
        if (!quiet) {
            std::printf("%-18s %6zu %3lld %3zu %5zu %5zu %6zu |", name.c_str(), mesh.vertex_count(), genus_of(mesh),
                        r.domain.levels.size(), r.domain.base.vertex_count(), r.map.unplaced, r.fallbacks);
            for (const auto& l : levels)
                std::printf(" %.2e/%.2e%s", l["rms"].get<double>(), l["hausdorff"].get<double>(),
                            l.contains("quadric_rms")
                                ? (" (q " + std::to_string(l["quadric_rms"].get<double>()).substr(0, 8) + ")").c_str()
                                : "");
            std::printf(" | %.2f s\n", total_ms / 1e3);
        }
    } catch (const std::exception& e) {
        row["status"] = "failed";
        row["error"] = e.what();
        if (!quiet) std::printf("%-18s FAILED: %s\n", name.c_str(), e.what());
    }
    return row;
}

// The finest level's error under the paper's flattening and guards against gimg's defaults (polar
// radii, cone tips kept) and with remesh smoothing, on the genus-0 meshes.
nlohmann::json variant_row(Context& ctx, const std::string& path, const MapsBenchOptions& o, bool quiet) try {
    const geo::Mesh mesh = geo::load_mesh(path);
    const std::string name = std::filesystem::path(path).filename().string();
    nlohmann::json row{{"mesh", name}};
    if (genus_of(mesh) != 0) return nullptr;
    geo::SurfaceDistanceOptions so;
    so.sampling.sample_count = o.samples;
    if (!quiet) std::printf("%-18s", name.c_str());
    using passes::RingFlattening;
    for (const auto& [key, flattening, cone, smoothing] :
         {std::tuple{"paper", RingFlattening::Za, 0.0, 0u}, std::tuple{"za_cone2", RingFlattening::Za, 2.0, 0u},
          std::tuple{"polar", RingFlattening::Polar, 0.0, 0u}, std::tuple{"defaults", RingFlattening::Polar, 2.0, 0u},
          std::tuple{"defaults_smooth20", RingFlattening::Polar, 2.0, 20u}}) {
        passes::MapsOptions mo;
        mo.flattening = flattening;
        mo.max_cone = cone;
        mo.smoothing = smoothing;
        const passes::MapsRemesh r = passes::maps_remesh(&ctx, mesh, mo, o.levels);
        const geo::SurfaceDistance d = geo::surface_distance(mesh, r.remesh.level_mesh(o.levels), so);
        row[key] = {{"rms", relative(d, false)}, {"hausdorff", relative(d, true)}};
        if (!quiet) std::printf("  %.2e/%.2e", relative(d, false), relative(d, true));
    }
    if (!quiet) std::printf("\n");
    return row;
} catch (const std::exception&) {
    return nullptr;  // the main table reports the failure
}

nlohmann::json wavelet_rows(Context& ctx, const std::string& path, std::uint32_t levels, std::uint64_t samples,
                            bool quiet) {
    const geo::Mesh mesh = geo::load_mesh(path);
    const passes::MapsRemesh r = passes::maps_remesh(&ctx, mesh, {}, levels);
    const double diagonal = mesh.bounds().diagonal();
    geo::SurfaceDistanceOptions so;
    so.sampling.sample_count = samples;
    nlohmann::json rows = nlohmann::json::array();
    for (int k : {-1, 0, 1, 2}) {
        const MapsWavelets w = maps_wavelets(&ctx, r.remesh, k, 0.0);
        const geo::SurfaceDistance down = geo::surface_distance(mesh, w.coarse, so);
        nlohmann::json row{{"mesh", std::filesystem::path(path).filename().string()},
                           {"k", k < 0 ? "lazy" : std::to_string(k)},
                           {"one_level_down_rms", relative(down, false)}};
        if (!quiet)
            std::printf("%-18s %5s  one level down %.3e |", row["mesh"].get<std::string>().c_str(),
                        row["k"].get<std::string>().c_str(), relative(down, false));
        passes::WaveletFilters filters = passes::wavelet_filters(r.remesh, k);
        for (double fraction : {0.10, 0.25, 0.50}) {
            std::vector<glm::dvec3> c = w.coefficients;
            passes::keep_largest_details(r.remesh, c, fraction);
            passes::wavelet_synthesis(r.remesh, filters, c);
            double sum = 0.0;
            for (std::size_t i = 0; i < c.size(); ++i) {
                const double d = glm::distance(c[i], r.remesh.positions[i]);
                sum += d * d;
            }
            const double rms = std::sqrt(sum / double(c.size())) / diagonal;
            row["kept_" + std::to_string(int(std::lround(fraction * 100))) + "_rms"] = rms;
            if (!quiet) std::printf("  %2.0f%%: %.3e", fraction * 100, rms);
        }
        if (!quiet) std::printf("\n");
        rows.push_back(row);
    }
    return rows;
}

// The GPU passes alone, as an embedding renderer runs them again and again: inputs uploaded and the
// plan compiled once, then executed `runs` times (median ms).
double resident_passes_ms(Context& ctx, const geo::Mesh& mesh, const passes::MapsRemesh& r, std::uint64_t runs,
                          bool wavelets) {
    const auto& points = r.remesh.base_point;
    std::vector<std::uint32_t> faces;
    std::vector<double> bary;
    for (const passes::SurfacePoint& p : points) {
        faces.push_back(p.face);
        bary.insert(bary.end(), {p.bary.x, p.bary.y, p.bary.z});
    }
    passes::InverseMapBuffers map = passes::upload_inverse_map(ctx, mesh, r.map);
    const passes::WaveletFilters filters = passes::wavelet_filters(r.remesh, 1);
    passes::WaveletBuffers wave = passes::upload_wavelet_filters(ctx, r.remesh, filters);
    Buffer face_buffer = upload_buffer(ctx, faces, "bench points");
    Buffer bary_buffer = upload_buffer(ctx, bary, "bench bary");
    Buffer out = ctx.create_buffer({32 * points.size(), "bench positions"});
    Buffer values = ctx.create_buffer({24 * points.size(), "bench values"});
    Graph g(ctx);
    if (wavelets) {
        auto v = g.import_buffer(values);
        v = passes::add_wavelet_analysis(g, v, r.remesh, wave);
        passes::add_wavelet_synthesis(g, v, r.remesh, wave);
    } else {
        passes::add_inverse_map(g, map, g.import_buffer(face_buffer), g.import_buffer(bary_buffer),
                                g.import_buffer(out), std::uint32_t(points.size()));
    }
    Plan plan = g.compile();
    plan.execute();  // first run: pipelines and transient resources
    std::vector<double> t;
    for (std::uint64_t i = 0; i < runs; ++i) t.push_back(time_ms([&] { plan.execute(); }));
    return median(t);
}

nlohmann::json timing_rows(Context& ctx, const std::string& path, std::uint32_t levels, std::uint64_t runs,
                           bool quiet) {
    const geo::Mesh mesh = geo::load_mesh(path);
    std::vector<double> gpu_total, cpu_total, gpu_eval, cpu_eval, gpu_wave, cpu_wave, base_s;
    for (std::uint64_t run = 0; run < runs; ++run) {
        for (Context* c : {&ctx, static_cast<Context*>(nullptr)}) {
            passes::MapsRemesh r;
            MapsWavelets w;
            const double total = time_ms([&] {
                r = passes::maps_remesh(c, mesh, {}, levels);
                w = maps_wavelets(c, r.remesh, 1, 0.0);
            });
            (c ? gpu_total : cpu_total).push_back(total);
            (c ? gpu_eval : cpu_eval).push_back(r.evaluate_seconds * 1e3);
            (c ? gpu_wave : cpu_wave).push_back((w.analysis_seconds + w.synthesis_seconds) * 1e3);
            base_s.push_back(r.base_seconds * 1e3);
        }
    }
    const passes::MapsRemesh resident = passes::maps_remesh(nullptr, mesh, {}, levels);
    const double map_pass = resident_passes_ms(ctx, mesh, resident, runs, false);
    const double wave_pass = resident_passes_ms(ctx, mesh, resident, runs, true);
    nlohmann::json j{{"mesh", std::filesystem::path(path).filename().string()},
                     {"levels", levels},
                     {"evaluate_pass_ms", map_pass},
                     {"wavelet_passes_ms", wave_pass},
                     {"runs", runs},
                     {"base_domain_ms", median(base_s)},
                     {"total_gpu_ms", median(gpu_total)},
                     {"total_cpu_ms", median(cpu_total)},
                     {"evaluate_gpu_ms", median(gpu_eval)},
                     {"evaluate_cpu_ms", median(cpu_eval)},
                     {"wavelets_gpu_ms", median(gpu_wave)},
                     {"wavelets_cpu_ms", median(cpu_wave)}};
    if (!quiet)
        std::printf(
            "%s to level %u, medians of %llu: whole pipeline (remesh + k = 1 analysis and synthesis) GPU "
            "%.0f ms, CPU twins %.0f ms; base domain %.0f ms; point evaluation GPU %.1f ms vs CPU %.1f ms "
            "(%.2fx); wavelets GPU %.1f ms vs CPU %.1f ms (%.2fx)\n",
            j["mesh"].get<std::string>().c_str(), levels, static_cast<unsigned long long>(runs), median(gpu_total),
            median(cpu_total), median(base_s), median(gpu_eval), median(cpu_eval), median(cpu_eval) / median(gpu_eval),
            median(gpu_wave), median(cpu_wave), median(cpu_wave) / median(gpu_wave));
    if (!quiet)
        std::printf(
            "the passes alone (uploaded and compiled once): point evaluation %.1f ms (%.2fx the CPU twin), "
            "wavelet analysis + synthesis %.1f ms (%.2fx)\n",
            map_pass, median(cpu_eval) / map_pass, wave_pass, median(cpu_wave) / wave_pass);
    return j;
}

void run_maps_bench(const MapsBenchOptions& o, const GlobalOptions& global) {
    std::vector<std::string> meshes = o.meshes;
    if (meshes.empty())
        for (const char* n : kClosedMeshes) meshes.push_back((shared_mesh_dir() / n).string());
    auto context = open_context(global);
    Context& ctx = *context;
    if (!global.quiet)
        std::printf(
            "gimg bench maps: remesh to level %u; per level RMS/Hausdorff relative to the diagonal "
            "(q: quadric decimation to the same vertex count)\n%-18s %6s %3s %3s %5s %5s %6s | levels 1..%u\n",
            o.levels, "mesh", "V", "g", "L", "base", "unpl", "fallb", o.levels);
    nlohmann::json rows = nlohmann::json::array();
    std::size_t failures = 0;
    for (const std::string& m : meshes) {
        rows.push_back(mesh_row(ctx, m, o, global.quiet));
        failures += rows.back()["status"] != "ok";
    }
    if (!global.quiet)
        std::printf(
            "\nlevel %u RMS/Hausdorff, genus 0: the paper (z^a, no cone guard), z^a + cone guard, polar, "
            "the defaults (polar + cone guard), the defaults + --smooth 20\n",
            o.levels);
    nlohmann::json variants = nlohmann::json::array();
    for (const std::string& m : meshes)
        if (auto row = variant_row(ctx, m, o, global.quiet); !row.is_null()) variants.push_back(row);
    if (!global.quiet)
        std::printf("\nwavelets: vertex RMS of the level-%u remesh rebuilt from the largest details\n", o.levels - 1);
    nlohmann::json wavelets = nlohmann::json::array();
    for (const std::string& m : or_defaults(o.wavelet_meshes, {"bunny.off", "armadillo.off", "knot1.off"}))
        for (auto& row : wavelet_rows(ctx, m, o.levels - 1, o.samples, global.quiet)) wavelets.push_back(row);
    if (!global.quiet) std::printf("\n");
    const std::string time_mesh = o.time_mesh.empty() ? (shared_mesh_dir() / "armadillo.off").string() : o.time_mesh;
    nlohmann::json timing = timing_rows(ctx, time_mesh, o.levels, o.runs, global.quiet);
    nlohmann::json j{{"levels", o.levels},   {"failures", failures}, {"meshes", rows},
                     {"variants", variants}, {"wavelets", wavelets}, {"timing", timing}};
    add_machine_figures(j, &ctx);
    write_json(o.json, j);
}

}  // namespace

void add_bench_maps_command(CLI::App& bench, const GlobalOptions& global) {
    auto o = std::make_shared<MapsBenchOptions>();
    auto* cmd = bench.add_subcommand("maps", "MAPS remesh error, wavelets and time on the closed shared meshes");
    cmd->add_option("--mesh", o->meshes, "Closed meshes to remesh (default: every closed shared mesh)");
    add_count_option(cmd, "--levels", o->levels, 2, 6, "Remesh levels (default 5)");
    cmd->add_option("--wavelet-mesh", o->wavelet_meshes,
                    "Meshes for the wavelet table (default bunny, armadillo, knot1)");
    cmd->add_option("--time-mesh", o->time_mesh, "Mesh for the pipeline timing (default armadillo)");
    add_count_option(cmd, "--runs", o->runs, 1, 100, "Timing runs, medians (default 3)");
    add_count_option(cmd, "--samples", o->samples, 1000, 100'000'000, "Surface samples per distance (default 300000)");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] { run_writing({}, {json_output(o->json)}, [&] { run_maps_bench(*o, global); }); });
}

}  // namespace gimg::cli

#pragma once
// Each gimg command lives in its own cmd_<name>.cpp and registers itself on the CLI11 app here.

#include <CLI/CLI.hpp>

#include "gimg/engine/context.h"
#include "gimg/geometry/mesh.h"
#include "gimg/geometry/topology.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace gimg::cli {

struct GlobalOptions {
    bool verbose = false;
    bool quiet = false;
    // Set by `gimg batch` for the commands it runs: the one device of the whole run.
    std::shared_ptr<Context> context;
};

// Every command below on `app` (main.cpp); `gimg batch` builds an app of them per model.
void add_commands(CLI::App& app, GlobalOptions& global);
// gimg batch COMMAND --inputs DIR|LIST --out DIR [--shard K/N] [--resume] [-- OPTIONS], and
// gimg batch merge DIR... (cmd_batch.cpp)
void add_batch_commands(CLI::App& app, const GlobalOptions& global);
void add_devices_command(CLI::App& app, const GlobalOptions& global);
void add_demo_command(CLI::App& app, const GlobalOptions& global);
// gimg compare A B [--json FILE] [--samples N] [--seed S]  (cmd_compare.cpp)
void add_compare_command(CLI::App& app, const GlobalOptions& global);
void add_cylinder_command(CLI::App& app, const GlobalOptions& global);
void add_render_command(CLI::App& app, const GlobalOptions& global);
void add_bench_command(CLI::App& app, const GlobalOptions& global);
// gimg bench sphere [--mesh PATH]... [--runs N] [--json FILE] (cmd_bench_sphere.cpp), under `bench`
void add_bench_sphere_command(CLI::App& bench, const GlobalOptions& global);
// gimg bench hierarchical [--mesh PATH]... [--size N]... (cmd_bench_hierarchy.cpp), under `bench`
void add_bench_hierarchy_command(CLI::App& bench, const GlobalOptions& global);
// gimg bench gim [--mesh PATH]... [--size N]... (cmd_bench_gim.cpp), under `bench`
void add_bench_gim_command(CLI::App& bench, const GlobalOptions& global);
// gimg bench quadmap [--region MESH:SIDE]... (cmd_bench_quadmap.cpp), under `bench`
void add_bench_quadmap_command(CLI::App& bench, const GlobalOptions& global);
// gimg bench maps [--mesh PATH]... [--levels J] (cmd_bench_maps.cpp), under `bench`
void add_bench_maps_command(CLI::App& bench, const GlobalOptions& global);
// gimg bench retrieval [--models N] (cmd_bench_retrieval.cpp), under `bench`
void add_bench_retrieval_command(CLI::App& bench, const GlobalOptions& global);
// gimg bench engine [--runs N] [--chain N] (cmd_bench_engine.cpp), under `bench`
void add_bench_engine_command(CLI::App& bench, const GlobalOptions& global);
void add_reconstruct_command(CLI::App& app, const GlobalOptions& global);
void add_sample_command(CLI::App& app, const GlobalOptions& global);
void add_roundtrip_command(CLI::App& app, const GlobalOptions& global);
// gimg sphere MESH --out DIR [--method harmonic|kanai|gu|linear] [--json FILE] (cmd_sphere.cpp)
void add_sphere_command(CLI::App& app, const GlobalOptions& global);
// DIR/checker.png (the mesh textured through its sphere map `y`) and DIR/sphere.png (cmd_sphere.cpp).
void write_sphere_pictures(Context& ctx, const geo::Mesh& mesh, const std::vector<glm::dvec3>& y,
                           const std::filesystem::path& dir);
// gimg index / search / eval (cmd_retrieval.cpp)
void add_retrieval_commands(CLI::App& app, const GlobalOptions& global);
// gimg gim MESH --out DIR [--size N] [--variant V] (cmd_gim.cpp)
void add_gim_command(CLI::App& app, const GlobalOptions& global);
// gimg quadmap / deform MESH --corners A,B,C,D --out DIR (cmd_quadmap.cpp)
void add_quadmap_commands(CLI::App& app, const GlobalOptions& global);
// gimg maps MESH --levels J --out DIR [--base N] [--k K] [--compress R] (cmd_maps.cpp)
void add_maps_command(CLI::App& app, const GlobalOptions& global);
// gimg polycube MESH --out DIR [--dz D] [--da A] [--k K] (cmd_polycube.cpp)
void add_polycube_command(CLI::App& app, const GlobalOptions& global);
// gimg info MESH [--json FILE] [--weld] (cmd_info.cpp)
void add_info_command(CLI::App& app, const GlobalOptions& global);
// The topology keys of info's JSON that DESIGN.md fixes, with `manifold` and `oriented`; repair's
// `before` and `after` too (cmd_info.cpp).
nlohmann::json topology_json(const geo::MeshInfo& info);
// The genus per component as info prints it: "0" for one component, "0, 1, -" for a few, "0 x30,
// 1 x2, - x1" for many ("-": undefined).
std::string genus_text(const geo::MeshInfo& info);
// gimg repair MESH --out FILE [--weld] [--largest] [--json FILE] (cmd_repair.cpp)
void add_repair_command(CLI::App& app, const GlobalOptions& global);

}  // namespace gimg::cli

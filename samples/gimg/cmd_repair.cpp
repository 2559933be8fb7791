// gimg repair MESH --out FILE [--weld] [--largest] [--json FILE]: a mesh made manifold and oriented,
// its collapsed, duplicate and zero-area faces removed (gimg/geometry/repair.h), without moving a
// vertex; what changed, and the result's topology.

#include "command_files.h"
#include "commands.h"
#include "json_output.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/repair.h"
#include "gimg/geometry/topology.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

namespace gimg::cli {

namespace {

struct RepairArgs {
    std::string mesh, out, json;
    geo::RepairOptions options;
};

nlohmann::json report_json(const geo::RepairReport& r) {
    return {{"welded_vertices", r.welded_vertices}, {"collapsed_faces", r.collapsed_faces},
            {"duplicate_faces", r.duplicate_faces}, {"turned_faces", r.turned_faces},
            {"opened_edges", r.opened_edges},       {"split_vertices", r.split_vertices},
            {"dropped_faces", r.dropped_faces},     {"zero_area_faces", r.zero_area_faces},
            {"flipped_edges", r.flipped_edges},     {"collapsed_edges", r.collapsed_edges},
            {"zero_area_left", r.zero_area_left},   {"dropped_pieces", r.dropped_pieces},
            {"unused_vertices", r.unused_vertices}, {"changed", r.changed()}};
}

void print_report(const RepairArgs& args, const geo::MeshInfo& before, const geo::RepairReport& r,
                  const geo::MeshInfo& after) {
    std::printf("%s: %zu vertices, %zu faces -> %zu vertices, %zu faces\n", args.mesh.c_str(), before.vertices,
                before.faces, after.vertices, after.faces);
    if (!r.changed()) std::printf("  nothing to repair\n");
    if (r.welded_vertices) std::printf("  welded     %zu vertices at identical positions\n", r.welded_vertices);
    if (r.collapsed_faces + r.duplicate_faces)
        std::printf("  removed    %zu faces with a repeated vertex, %zu duplicate faces\n", r.collapsed_faces,
                    r.duplicate_faces);
    if (r.turned_faces) std::printf("  turned     %zu faces to agree with their piece\n", r.turned_faces);
    if (r.opened_edges + r.split_vertices + r.dropped_faces)
        std::printf(
            "  opened     %zu edges of more than two faces or of a non-orientable loop; %zu vertices "
            "copied, one per fan; %zu faces dropped\n",
            r.opened_edges, r.split_vertices, r.dropped_faces);
    if (r.zero_area_faces)
        std::printf("  zero area  %zu faces: %zu edges flipped, %zu collapsed, %zu faces left\n", r.zero_area_faces,
                    r.flipped_edges, r.collapsed_edges, r.zero_area_left);
    if (r.dropped_pieces) std::printf("  pieces     the largest kept, %zu dropped\n", r.dropped_pieces);
    if (r.unused_vertices) std::printf("  unused     %zu vertices in no face removed\n", r.unused_vertices);
    std::printf("  result     %s, %s, %zu piece%s of genus %s, %zu boundary loops, %zu faces of zero area\n",
                after.manifold ? "manifold" : "NOT manifold", after.oriented ? "oriented" : "NOT oriented",
                after.components, after.components == 1 ? "" : "s", genus_text(after).c_str(), after.boundary_loops,
                after.zero_area_faces);
}

void run_repair(const RepairArgs& args, const GlobalOptions& global) {
    const auto start = std::chrono::steady_clock::now();
    geo::Mesh mesh = geo::load_mesh(args.mesh);
    const geo::MeshInfo before = geo::analyze_topology(mesh);
    const geo::RepairReport report = geo::repair_mesh(mesh, args.options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (mesh.triangles.empty())
        throw geo::InputError(
            "repair: no face is left (every face repeats a vertex, repeats an earlier face or "
            "has no area)");
    const geo::MeshInfo after = geo::analyze_topology(mesh);
    geo::save_mesh(mesh, args.out);
    if (!global.quiet) {
        print_report(args, before, report, after);
        std::printf("wrote %s\n", args.out.c_str());
    }
    write_json(args.json, {{"mesh", args.mesh},
                           {"out", args.out},
                           {"weld", args.options.weld},
                           {"largest", args.options.largest},
                           {"before", topology_json(before)},
                           {"repair", report_json(report)},
                           {"after", topology_json(after)},
                           {"seconds", seconds}});
}

}  // namespace

void add_repair_command(CLI::App& app, const GlobalOptions& global) {
    auto args = std::make_shared<RepairArgs>();
    CLI::App* cmd = app.add_subcommand(
        "repair", "Make a mesh manifold and oriented, without collapsed, duplicate or zero-area faces");
    cmd->add_option("MESH", args->mesh, "Mesh file: .obj, .ply, .off, .stl")->required();
    cmd->add_option("--out", args->out, "The repaired mesh (.ply or .obj)")->required();
    cmd->add_flag("--weld", args->options.weld, "Merge vertices at identical positions first (STL, polygon soups)");
    cmd->add_flag("--largest", args->options.largest, "Keep only the piece of most faces");
    cmd->add_option("--json", args->json, "Also write the figures as JSON to FILE")->type_name("FILE");
    cmd->callback([args, &global] {
        run_writing({args->mesh}, {{"--out", args->out, {".ply", ".obj"}}, json_output(args->json)},
                    [&] { run_repair(*args, global); });
    });
}

}  // namespace gimg::cli

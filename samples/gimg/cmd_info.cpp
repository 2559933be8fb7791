// gimg info MESH [--json FILE] [--weld]: a mesh's counts, topology and defects, as a short
// summary and optionally as JSON (keys fixed by DESIGN.md, documented in the README).

#include "command_files.h"
#include "commands.h"
#include "json_output.h"

#include "gimg/geometry/io.h"
#include "gimg/geometry/topology.h"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>

namespace gimg::cli {

namespace {

struct InfoArgs {
    std::string mesh;
    std::string json;
    bool weld = false;
};

nlohmann::json vec3(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json to_json(const std::string& file, const geo::LoadReport& load, const geo::MeshInfo& info,
                       double seconds) {
    nlohmann::json chi = nlohmann::json::array(), faces = nlohmann::json::array(), vertices = nlohmann::json::array(),
                   loops = nlohmann::json::array(), manifold = nlohmann::json::array(),
                   orientable = nlohmann::json::array(), oriented = nlohmann::json::array();
    for (const geo::ComponentInfo& c : info.component_info) {
        chi.push_back(c.euler_characteristic);
        faces.push_back(c.faces);
        vertices.push_back(c.vertices);
        loops.push_back(c.boundary_loops);
        manifold.push_back(c.manifold);
        orientable.push_back(c.orientable);
        oriented.push_back(c.oriented);
    }
    nlohmann::json j = topology_json(info);
    j.update({
        {"bbox_min", vec3(info.bbox.min)},
        {"bbox_max", vec3(info.bbox.max)},
        // More.
        {"file", file},
        {"format", load.format},
        {"encoding", load.encoding},
        {"file_vertices", load.file_vertices},
        {"file_faces", load.file_faces},
        {"polygons_triangulated", load.polygons_triangulated},
        {"welded", load.welded},
        {"welded_vertices", load.welded_vertices},
        {"isolated_vertices", info.isolated_vertices},
        {"boundary_edges", info.boundary_edges},
        {"wire_edges", info.wire_edges},
        {"collapsed_faces", info.collapsed_faces},
        {"zero_area_faces", info.zero_area_faces},
        {"nan_coordinates", info.nonfinite_vertices},
        {"inconsistent_edges", info.inconsistent_edges},
        {"closed", info.closed},
        {"manifold", info.manifold},
        {"orientable", info.orientable},
        {"oriented", info.oriented},
        {"euler_characteristic", chi},
        {"component_faces", faces},
        {"component_vertices", vertices},
        {"component_boundary_loops", loops},
        {"component_manifold", manifold},
        {"component_orientable", orientable},
        {"component_oriented", oriented},
        {"bbox_diagonal", info.bbox.diagonal()},
        {"notes", load.notes},
        {"seconds", seconds},
    });
    return j;
}

}  // namespace

std::string genus_text(const geo::MeshInfo& info) {
    auto one = [](const geo::ComponentInfo& c) { return c.genus ? std::to_string(*c.genus) : std::string("-"); };
    std::string out;
    if (info.component_info.size() <= 8) {
        for (const geo::ComponentInfo& c : info.component_info) out += (out.empty() ? "" : ", ") + one(c);
        return out;
    }
    std::map<std::string, std::size_t> histogram;
    for (const geo::ComponentInfo& c : info.component_info) ++histogram[one(c)];
    for (const auto& [genus, count] : histogram)
        out += (out.empty() ? "" : ", ") + genus + " x" + std::to_string(count);
    return out;
}

namespace {

const char* yes_no(bool b) { return b ? "yes" : "no"; }

void print_summary(const std::string& file, const geo::LoadReport& load, const geo::MeshInfo& info) {
    std::string format = load.format;
    for (char& c : format) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::printf("%s: %s (%s), %zu vertices, %zu triangles from %zu faces\n", file.c_str(), format.c_str(),
                load.encoding.c_str(), info.vertices, info.faces, load.file_faces);
    std::printf("  edges            %zu\n", info.edges);
    std::printf("  components       %zu (isolated vertices: %zu)\n", info.components, info.isolated_vertices);
    std::printf("  boundary loops   %zu (%zu boundary edges)%s\n", info.boundary_loops, info.boundary_edges,
                info.closed ? ", closed" : "");
    std::printf("  genus            %s   (per component, largest first; - where undefined)\n",
                genus_text(info).c_str());
    std::printf("  manifold         %s (non-manifold edges: %zu, vertices: %zu)\n", yes_no(info.manifold),
                info.non_manifold_edges, info.non_manifold_vertices);
    std::printf("  orientation      %s (orientable: %s, inconsistent edges: %zu)\n",
                info.oriented ? "consistent" : "inconsistent", yes_no(info.orientable), info.inconsistent_edges);
    std::printf("  degenerate faces %zu (repeated vertex: %zu, zero area: %zu)\n", info.degenerate_faces,
                info.collapsed_faces, info.zero_area_faces);
    std::printf("  duplicate faces  %zu\n", info.duplicate_faces);
    std::printf("  NaN coordinates  %zu\n", info.nonfinite_vertices);
    std::printf("  bounding box     [%g, %g, %g] .. [%g, %g, %g], diagonal %g\n", info.bbox.min.x, info.bbox.min.y,
                info.bbox.min.z, info.bbox.max.x, info.bbox.max.y, info.bbox.max.z, info.bbox.diagonal());
    for (const std::string& note : load.notes) std::printf("  note: %s\n", note.c_str());
}

void run_info(const InfoArgs& args, const GlobalOptions& global) {
    const auto start = std::chrono::steady_clock::now();
    geo::LoadReport load;
    const geo::Mesh mesh = geo::load_mesh(args.mesh, geo::LoadOptions{.weld = args.weld}, &load);
    const geo::MeshInfo info = geo::analyze_topology(mesh);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!global.quiet) print_summary(args.mesh, load, info);
    write_json(args.json, to_json(args.mesh, load, info, seconds));
}

}  // namespace

nlohmann::json topology_json(const geo::MeshInfo& info) {
    nlohmann::json genus = nlohmann::json::array();
    for (const geo::ComponentInfo& c : info.component_info)
        genus.push_back(c.genus ? nlohmann::json(*c.genus) : nlohmann::json(nullptr));
    return {{"vertices", info.vertices},
            {"faces", info.faces},
            {"edges", info.edges},
            {"components", info.components},
            {"boundary_loops", info.boundary_loops},
            {"genus", genus},
            {"non_manifold_edges", info.non_manifold_edges},
            {"non_manifold_vertices", info.non_manifold_vertices},
            {"degenerate_faces", info.degenerate_faces},
            {"duplicate_faces", info.duplicate_faces},
            {"manifold", info.manifold},
            {"oriented", info.oriented}};
}

void add_info_command(CLI::App& app, const GlobalOptions& global) {
    auto args = std::make_shared<InfoArgs>();
    CLI::App* cmd = app.add_subcommand("info", "Print a mesh's counts, topology and defects");
    cmd->add_option("MESH", args->mesh, "Mesh file: .obj, .ply (ascii or binary), .off, .stl")->required();
    cmd->add_option("--json", args->json, "Also write the figures as JSON to FILE")->type_name("FILE");
    cmd->add_flag("--weld", args->weld, "Merge vertices at identical positions before the analysis");
    cmd->callback(
        [args, &global] { run_writing({args->mesh}, {json_output(args->json)}, [&] { run_info(*args, global); }); });
}

}  // namespace gimg::cli

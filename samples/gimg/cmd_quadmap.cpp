// gimg quadmap MESH --corners a,b,c,d|auto --out DIR [--weights ...] [--start ...] [--solver ...] [--json FILE]
// gimg deform MESH --corners a,b,c,d|auto (--lattice PxQ --offsets FILE | --paste HEIGHT.exr|bump --height H) --out DIR
// Four-sided regions mapped onto the unit square, and deformed through that map (docs/quadmap.md).
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "quad_corners.h"
#include "size_option.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/curvature.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/exr.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/normals.h"
#include "gimg/passes/quad_region.h"
#include "gimg/passes/render.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace gimg::cli {

namespace {

std::array<std::uint32_t, 4> parse_corners(const std::string& text, const geo::Mesh& mesh) {
    if (text == "auto") return automatic_corners(mesh);
    if (text.rfind("auto:", 0) == 0) {
        char* end = nullptr;
        const double side = std::strtod(text.c_str() + 5, &end);
        if (*end || !(side > 0.0 && side <= 2.0))
            throw geo::InputError(
                "--corners auto:F takes the square's side F in bounding-box diagonals (0 to 2), got '" + text + "'");
        return automatic_corners(mesh, side);
    }
    std::array<std::uint32_t, 4> c{};
    std::istringstream in(text);
    char comma = 0;
    for (int i = 0; i < 4; ++i) {
        long long v = -1;
        if (!(in >> v) || v < 0 || v > 0xfffffffe || (i < 3 && (!(in >> comma) || comma != ',')))
            throw geo::InputError("--corners takes four vertex indices A,B,C,D (counter-clockwise) or auto, got '" +
                                  text + "'");
        c[i] = std::uint32_t(v);
    }
    if (!in.eof() && (in >> std::ws, !in.eof()))
        throw geo::InputError("--corners takes four vertex indices A,B,C,D or auto, got '" + text + "'");
    return c;
}

struct QuadOptions {
    std::string mesh, corners, out, json, weights = "floater", start = "dijkstra", solver = "krylov";
    std::string lattice, offsets, paste;
    double relaxation = 0.05, tau = 1e-4, height = 0.05;
    bool cpu = false;
};

passes::QuadMapOptions map_options(const QuadOptions& o) {
    passes::QuadMapOptions m;
    m.weights = o.weights == "chord" ? passes::QuadWeights::Chord : passes::QuadWeights::Floater;
    m.start = o.start == "flat" ? passes::QuadStart::Flat : passes::QuadStart::Dijkstra;
    m.solver = o.solver == "iterate"  ? passes::QuadSolver::Iterate
               : o.solver == "direct" ? passes::QuadSolver::Direct
                                      : passes::QuadSolver::Krylov;
    m.relaxation = o.relaxation;
    m.tau = o.tau;
    return m;
}

// A view from the side the region faces (its mean vertex normal), turned by `turn` degrees about
// the vertical so relief shows.
passes::View facing_view(const passes::QuadRegion& region, double turn) {
    glm::dvec3 n(0.0);
    for (const auto& v : geo::vertex_normals(region.mesh)) n += v;
    n = glm::length(n) > 0.0 ? glm::normalize(n) : glm::dvec3(0, 0, 1);
    return {.azimuth_deg = glm::degrees(std::atan2(n.x, n.z)) + turn,
            .elevation_deg = glm::degrees(std::asin(std::clamp(n.y, -0.99, 0.99)))};
}

// The region checkered through its map, the rest of the mesh in one plain colour.
geo::RgbaImage checker_picture(Context& ctx, const passes::QuadRegion& region, const std::vector<glm::dvec2>& uv) {
    geo::Mesh both = region.mesh;
    both.texcoords = uv;
    const auto offset = std::uint32_t(both.positions.size());
    for (const auto& p : region.outside.positions)
        both.positions.push_back(p), both.texcoords.push_back({-0.04, -0.04});
    for (const auto& t : region.outside.triangles) both.triangles.push_back(t + offset);
    passes::RenderOptions r;
    r.width = r.height = 640;
    r.color = passes::MeshColor::Checker;
    r.checker_cells = 8.0;
    r.view = facing_view(region, 0.0);
    geo::RgbaImage picture = passes::render_mesh(ctx, both, r);
    for (std::size_t i = 3; i < picture.pixels.size(); i += 4) picture.pixels[i] = 255;
    return picture;
}

nlohmann::json map_json(const passes::QuadRegion& region, const passes::QuadMap& m, const QuadOptions& o) {
    return {{"region_vertices", region.mesh.vertex_count()},
            {"region_faces", region.mesh.face_count()},
            {"inserted_points", region.inserted},
            {"merged_points", region.merged},
            {"corners",
             std::array<std::uint32_t, 4>{region.original[region.corners[0]], region.original[region.corners[1]],
                                          region.original[region.corners[2]], region.original[region.corners[3]]}},
            {"weights", o.weights},
            {"start", o.start},
            {"solver", o.solver},
            {"relaxation", o.relaxation},
            {"tau", o.tau},
            {"iterations_u", m.iterations_u},
            {"iterations_v", m.iterations_v},
            {"start_sweeps", m.start_sweeps},
            {"weight_fallbacks", m.weight_fallbacks},
            {"flipped", m.flipped},
            {"weights_ms", m.weights_ms},
            {"start_ms", m.start_ms},
            {"solve_ms", m.solve_ms}};
}

void run_quadmap(const QuadOptions& o, const GlobalOptions& global) {
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    const passes::QuadRegion region = passes::cut_quad_region(mesh, parse_corners(o.corners, mesh));
    auto ctx = open_context(global);
    const passes::QuadMap m = passes::map_quad_region(o.cpu ? nullptr : ctx.get(), region, map_options(o));
    const std::filesystem::path dir(o.out);
    geo::Mesh out = region.mesh;
    out.texcoords = m.uv;
    geo::save_mesh(out, dir / "region.obj");
    geo::write_png(checker_picture(*ctx, region, m.uv), dir / "checker.png");
    if (!global.quiet) {
        std::printf("%s: region of %zu vertices (%zu points inserted on edges, %zu merged), %zu faces\n",
                    o.mesh.c_str(), region.mesh.vertex_count(), region.inserted, region.merged,
                    region.mesh.face_count());
        std::printf(
            "%s weights (%.1f ms), %s start (%zu sweeps, %.1f ms), %s solve: u %zu, v %zu iterations, "
            "%.1f ms; %zu flipped\n",
            o.weights.c_str(), m.weights_ms, o.start.c_str(), m.start_sweeps, m.start_ms, o.solver.c_str(),
            m.iterations_u, m.iterations_v, m.solve_ms, m.flipped);
        std::printf("wrote %s/{region.obj, checker.png}\n", o.out.c_str());
    }
    nlohmann::json j = map_json(region, m, o);
    j["mesh"] = o.mesh;
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

passes::OffsetLattice read_lattice(const std::string& size, const std::string& path) {
    const auto [p, q] = parse_size(size);
    passes::OffsetLattice l{.columns = p, .rows = q};
    std::ifstream in(path);
    if (!in) throw geo::InputError(path + ": cannot read the offsets");
    glm::dvec3 d;
    while (in >> d.x >> d.y >> d.z) l.offsets.push_back(d);
    if (!in.eof()) throw geo::InputError(path + ": offsets are lines of three numbers x y z");
    if (l.offsets.size() != std::size_t(p) * q)
        throw geo::InputError(path + ": " + std::to_string(l.offsets.size()) + " offsets for a " + size +
                              " lattice (give " + std::to_string(std::size_t(p) * q) + ", row by row)");
    if (p < 4 || q < 4) throw geo::InputError("--lattice: at least 4x4 control points");
    return l;
}

void run_deform(const QuadOptions& o, const GlobalOptions& global) {
    if (o.lattice.empty() == o.paste.empty())
        throw geo::InputError("deform takes either --lattice PxQ with --offsets FILE, or --paste HEIGHT.exr|bump");
    if (!o.lattice.empty() && o.offsets.empty()) throw geo::InputError("--lattice needs --offsets FILE");
    passes::OffsetLattice lattice;
    passes::PastedFeature feature{.scale = o.height};
    if (!o.lattice.empty()) lattice = read_lattice(o.lattice, o.offsets);
    if (!o.paste.empty() && o.paste != "bump") {
        const geo::FloatImage h = geo::read_exr(o.paste);
        if (h.channels.empty()) throw geo::InputError(o.paste + ": no channel to read heights from");
        const auto& first = h.channels.count("R") ? h.channels.at("R") : h.channels.begin()->second;
        feature.width = h.width, feature.height = h.height;
        feature.heights = first;
    }
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    const passes::QuadRegion region = passes::cut_quad_region(mesh, parse_corners(o.corners, mesh));
    auto ctx = open_context(global);
    const passes::QuadMap m = passes::map_quad_region(o.cpu ? nullptr : ctx.get(), region, map_options(o));
    for (auto& d : lattice.offsets) d *= mesh.bounds().diagonal();  // given in bounding-box diagonals
    const geo::Mesh deformed = o.lattice.empty()
                                   ? (o.cpu ? passes::paste_feature(mesh, region, m.uv, feature)
                                            : passes::paste_feature_gpu(*ctx, mesh, region, m.uv, feature))
                                   : (o.cpu ? passes::deform_by_lattice(mesh, region, m.uv, lattice)
                                            : passes::deform_by_lattice_gpu(*ctx, mesh, region, m.uv, lattice));
    const std::filesystem::path dir(o.out);
    geo::save_mesh(deformed, dir / "deformed.ply");
    passes::RenderOptions r;
    r.width = r.height = 512;
    r.view = facing_view(region, 50.0);
    geo::RgbaImage picture = passes::render_side_by_side(*ctx, mesh, deformed, r);
    for (std::size_t i = 3; i < picture.pixels.size(); i += 4) picture.pixels[i] = 255;
    geo::write_png(picture, dir / "compare.png");
    if (!global.quiet)
        std::printf("%s: region of %zu vertices mapped (%zu flipped); wrote %s/{deformed.ply, compare.png}\n",
                    o.mesh.c_str(), region.mesh.vertex_count(), m.flipped, o.out.c_str());
    nlohmann::json j = map_json(region, m, o);
    j["mesh"] = o.mesh;
    j["deformation"] = o.lattice.empty() ? "paste" : "lattice";
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

void add_map_options(CLI::App* cmd, QuadOptions& o) {
    cmd->add_option("mesh", o.mesh, "Input mesh")->required();
    cmd->add_option("--corners", o.corners,
                    "Four vertex indices A,B,C,D counter-clockwise seen from outside (to (0,0), (1,0), (1,1), (0,1)), "
                    "or auto[:F] (a square of side F diagonals, default 0.2, around the flattest vertex)")
        ->required();
    cmd->add_option("--weights", o.weights, "floater (shape-preserving, default) or chord")
        ->check(CLI::IsMember({"floater", "chord"}));
    cmd->add_option("--start", o.start, "dijkstra (the accelerated start, default) or flat (0.5)")
        ->check(CLI::IsMember({"dijkstra", "flat"}));
    cmd->add_option("--solver", o.solver,
                    "krylov (BiCGSTAB on the GPU, default), iterate (the paper's relaxation) or direct (SparseLU)")
        ->check(CLI::IsMember({"krylov", "iterate", "direct"}));
    add_number_option(cmd, "--relaxation", o.relaxation, 0.0, 0.999, "k of the relaxation (default 0.05)");
    add_number_option(cmd, "--tau", o.tau, 1e-15, 1.0,
                      "the relaxation stops when every correction is below this (default 1e-4)");
    cmd->add_flag("--cpu", o.cpu, "Solve (and deform) with the CPU twins");
    cmd->add_option("--json", o.json, "Write the figures as JSON");
}

}  // namespace

void add_quadmap_commands(CLI::App& app, const GlobalOptions& global) {
    auto q = std::make_shared<QuadOptions>();
    auto* quadmap = app.add_subcommand("quadmap", "Map a four-sided region of a mesh onto the unit square");
    add_map_options(quadmap, *q);
    quadmap->add_option("--out", q->out, "Output folder (region.obj, checker.png)")->required();
    quadmap->callback([q, &global] {
        auto outputs = folder_outputs("--out", q->out, {"region.obj", "checker.png"});
        outputs.push_back(json_output(q->json));
        run_writing({q->mesh}, outputs, [&] {
            make_output_folder("--out", q->out);
            run_quadmap(*q, global);
        });
    });

    auto d = std::make_shared<QuadOptions>();
    auto* deform =
        app.add_subcommand("deform", "Deform a four-sided region through its map: a lattice or a pasted feature");
    add_map_options(deform, *d);
    deform->add_option("--out", d->out, "Output folder (deformed.ply, compare.png)")->required();
    deform->add_option("--lattice", d->lattice, "Control points PxQ of the offset lattice (clamped cubic B-splines)");
    deform->add_option(
        "--offsets", d->offsets,
        "Text file of P*Q offsets 'x y z' in bounding-box diagonals, row by row (v); the outer three rows "
        "and columns are fixed at zero");
    deform->add_option("--paste", d->paste, "A height map (EXR: its R channel, or its first, over the square) or bump");
    add_number_option(deform, "--height", d->height, -1e3, 1e3,
                      "Height of the pasted feature, in bounding-box diagonals (default 0.05)");
    deform->callback([d, &global] {
        auto outputs = folder_outputs("--out", d->out, {"deformed.ply", "compare.png"});
        outputs.push_back(json_output(d->json));
        std::vector<std::filesystem::path> inputs{d->mesh};
        if (!d->offsets.empty()) inputs.push_back(d->offsets);
        if (!d->paste.empty() && d->paste != "bump") inputs.push_back(d->paste);
        run_writing(inputs, outputs, [&] {
            make_output_folder("--out", d->out);
            run_deform(*d, global);
        });
    });
}

}  // namespace gimg::cli

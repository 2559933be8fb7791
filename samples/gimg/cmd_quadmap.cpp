// gimg quadmap MESH --corners a,b,c,d|auto --out DIR [--weights ...] [--start ...] [--solver ...] [--json FILE]
// gimg deform MESH --corners a,b,c,d|auto (--lattice PxQ --offsets FILE | --paste HEIGHT.exr|bump --height H) --out DIR
// Four-sided regions mapped onto the unit square, and deformed through that map (docs/quadmap.md).
#include "command_files.h"
#include "commands.h"
#include "corner_option.h"
#include "gpu_context.h"
#include "json_output.h"
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
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace gimg::cli {

namespace {

std::array<std::uint32_t, 4> four_corners(const std::vector<std::uint32_t>& c) {
    if (c.size() != 4) throw geo::InputError("deform takes a region of four corners");
    return {c[0], c[1], c[2], c[3]};
}

struct QuadOptions {
    std::string mesh, corners, out, json, weights = "floater", start = "overrelaxed", solver = "krylov";
    std::string lattice, polar, offsets, paste;
    double relaxation = 0.05, tau = 1e-4, height = 0.05;
    bool cpu = false;
};

passes::QuadMapOptions map_options(const QuadOptions& o) {
    passes::QuadMapOptions m;
    m.weights = o.weights == "chord" ? passes::QuadWeights::Chord : passes::QuadWeights::Floater;
    m.start = o.start == "flat"       ? passes::QuadStart::Flat
              : o.start == "dijkstra" ? passes::QuadStart::Dijkstra
                                      : passes::QuadStart::Overrelaxed;
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
            {"start_folded", m.start_folded},
            {"overrelaxed_sweeps", m.overrelaxed_sweeps},
            {"weight_fallbacks", m.weight_fallbacks},
            {"flipped", m.flipped},
            {"weights_ms", m.weights_ms},
            {"start_ms", m.start_ms},
            {"solve_ms", m.solve_ms}};
}

// Three corners: barycentric coordinates; region.obj carries them as (u, v) on an equilateral
// triangle, (beta + gamma / 2, gamma sqrt(3) / 2).
void run_triangle(const QuadOptions& o, const GlobalOptions& global, const passes::QuadRegion& region, Context& ctx) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<glm::dvec3> bary =
        passes::barycentric_map(o.cpu ? nullptr : &ctx, region,
                                o.weights == "chord" ? passes::QuadWeights::Chord : passes::QuadWeights::Floater);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::vector<glm::dvec2> uv(bary.size());
    for (std::size_t i = 0; i < uv.size(); ++i) uv[i] = {bary[i].y + 0.5 * bary[i].z, bary[i].z * std::sqrt(3.0) / 2.0};
    geo::Mesh out = region.mesh;
    out.texcoords = uv;
    const std::filesystem::path dir(o.out);
    geo::save_mesh(out, dir / "region.obj", {.double_precision = true});  // as gim's param.obj
    geo::write_png(checker_picture(ctx, region, uv), dir / "checker.png");
    std::size_t flipped = 0;
    for (const auto& t : out.triangles) {
        const glm::dvec2 a = uv[t.y] - uv[t.x], b = uv[t.z] - uv[t.x];
        flipped += a.x * b.y - a.y * b.x < 0.0;
    }
    if (!global.quiet)
        std::printf(
            "%s: triangle region of %zu vertices (%zu points inserted on edges), barycentric coordinates in "
            "%.1f ms, %zu flipped; wrote %s/{region.obj, checker.png}\n",
            o.mesh.c_str(), region.mesh.vertex_count(), region.inserted, ms, flipped, o.out.c_str());
    nlohmann::json j{{"mesh", o.mesh},
                     {"coordinates", "barycentric"},
                     {"region_vertices", region.mesh.vertex_count()},
                     {"region_faces", region.mesh.face_count()},
                     {"inserted_points", region.inserted},
                     {"merged_points", region.merged},
                     {"weights", o.weights},
                     {"flipped", flipped},
                     {"solve_ms", ms}};
    add_machine_figures(j, &ctx);
    write_json(o.json, j);
}

void run_quadmap(const QuadOptions& o, const GlobalOptions& global) {
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    const passes::QuadRegionCutter cutter(mesh);
    const std::vector<std::uint32_t> corners = parse_corners(o.corners, cutter);
    auto ctx = open_context(global);
    const std::filesystem::path dir(o.out);
    if (corners.size() == 3) {
        run_triangle(o, global, cutter.cut_triangle({corners[0], corners[1], corners[2]}), *ctx);
        return;
    }
    const passes::QuadRegion region = cutter.cut(four_corners(corners));
    const passes::QuadMap m = passes::map_quad_region(o.cpu ? nullptr : ctx.get(), region, map_options(o));
    geo::Mesh out = region.mesh;
    out.texcoords = m.uv;
    geo::save_mesh(out, dir / "region.obj", {.double_precision = true});  // as gim's param.obj
    geo::write_png(checker_picture(*ctx, region, m.uv), dir / "checker.png");
    if (!global.quiet) {
        std::printf("%s: region of %zu vertices (%zu points inserted on edges, %zu merged), %zu faces\n",
                    o.mesh.c_str(), region.mesh.vertex_count(), region.inserted, region.merged,
                    region.mesh.face_count());
        const std::string sweeps = m.overrelaxed_sweeps ? std::to_string(m.start_sweeps) + " + " +
                                                              std::to_string(m.overrelaxed_sweeps) + " over-relaxed"
                                                        : std::to_string(m.start_sweeps);
        std::printf(
            "%s weights (%.1f ms), %s start (%s sweeps, %.1f ms), %s solve: u %zu, v %zu iterations, "
            "%.1f ms; %zu flipped\n",
            o.weights.c_str(), m.weights_ms, o.start.c_str(), sweeps.c_str(), m.start_ms, o.solver.c_str(),
            m.iterations_u, m.iterations_v, m.solve_ms, m.flipped);
        if (m.start_folded)
            std::printf(
                "note: the corners fold the accelerated start's bilinear map (s1/s0 + t1/t0 <= 1, a dart-shaped "
                "region); the start took the root nearest the linear guess\n");
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
    if (int(!o.lattice.empty()) + int(!o.polar.empty()) + int(!o.paste.empty()) != 1)
        throw geo::InputError(
            "deform takes either --lattice PxQ or --polar-lattice RxS with --offsets FILE, or --paste HEIGHT.exr|bump");
    if ((!o.lattice.empty() || !o.polar.empty()) && o.offsets.empty())
        throw geo::InputError("a lattice needs --offsets FILE");
    passes::OffsetLattice lattice;
    passes::PastedFeature feature{.scale = o.height};
    passes::PolarLattice polar;
    if (!o.lattice.empty()) lattice = read_lattice(o.lattice, o.offsets);
    if (!o.polar.empty()) {
        const passes::OffsetLattice read = read_lattice(o.polar, o.offsets);
        polar = {.rings = read.columns, .sectors = read.rows, .offsets = read.offsets};
        polar.evaluate({0.5, 0.5});  // its own checks, before any work
    }
    if (!o.paste.empty() && o.paste != "bump") {
        const geo::FloatImage h = geo::read_exr(o.paste);
        if (h.channels.empty()) throw geo::InputError(o.paste + ": no channel to read heights from");
        const auto& first = h.channels.count("R") ? h.channels.at("R") : h.channels.begin()->second;
        feature.width = h.width, feature.height = h.height;
        feature.heights = first;
    }
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    const passes::QuadRegionCutter cutter(mesh);
    const passes::QuadRegion region = cutter.cut(four_corners(parse_corners(o.corners, cutter)));
    auto ctx = open_context(global);
    const passes::QuadMap m = passes::map_quad_region(o.cpu ? nullptr : ctx.get(), region, map_options(o));
    for (auto& d : lattice.offsets) d *= mesh.bounds().diagonal();  // given in bounding-box diagonals
    for (auto& d : polar.offsets) d *= mesh.bounds().diagonal();
    const geo::Mesh deformed = !o.polar.empty() ? passes::deform_by_polar_lattice(mesh, region, m.uv, polar)
                               : o.lattice.empty()
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
    j["deformation"] = !o.polar.empty() ? "polar lattice" : o.lattice.empty() ? "paste" : "lattice";
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
    cmd->add_option("--start", o.start,
                    "overrelaxed (the accelerated start, then 40 over-relaxed sweeps; default), dijkstra (the "
                    "paper's accelerated start) or flat (0.5)")
        ->check(CLI::IsMember({"overrelaxed", "dijkstra", "flat"}));
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

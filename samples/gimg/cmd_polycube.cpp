// gimg polycube MESH [--dz D] [--da A] [--k K] --out DIR [--json FILE]
// A closed or open mesh -> its polycube (Satoh & Imai, after He et al.) and the map onto it.
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/polycube.h"
#include "gimg/passes/render.h"

#include <cstdio>
#include <sstream>

namespace gimg::cli {

namespace {

struct PolycubeCommandOptions {
    std::string mesh, out, json, axis = "auto";
    double dz = 0.0, da = 0.05, retry_seconds = 60.0;
    std::uint32_t k = 2, max_level = 8, smooth = 10, slice_smoothing = 0;
    bool cpu = false, no_map = false, no_retry = false;
};

// The polyhedron as OBJ, its faces in two groups: the polycube, and the regions the mesh's holes map to.
void write_polycube_obj(const passes::Polycube& p, const std::filesystem::path& path) {
    std::ostringstream s;
    s.precision(17);
    s << "# gimg polycube: " << p.surface.vertex_count() << " vertices, " << p.surface.face_count()
      << " triangles; group hole: where the mesh's holes map\n";
    for (const auto& v : p.surface.positions) s << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
    for (int hole = 0; hole < 2; ++hole) {
        s << "g " << (hole ? "hole" : "polycube") << '\n';
        for (std::size_t f = 0; f < p.surface.face_count(); ++f)
            if (p.hole[f] == hole) {
                const auto& t = p.surface.triangles[f];
                s << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
            }
    }
    geo::write_file_atomically(path, s.str());
}

// Each triangle on its own, coloured by a scalar (its polycube face's axis; hole regions apart).
geo::Mesh unshared(const geo::Mesh& m, const std::vector<float>& per_face, std::vector<float>& scalars) {
    geo::Mesh out;
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        const std::uint32_t base = std::uint32_t(out.positions.size());
        for (int k = 0; k < 3; ++k) {
            out.positions.push_back(m.positions[m.triangles[f][k]]);
            scalars.push_back(per_face[f]);
        }
        out.triangles.push_back({base, base + 1, base + 2});
    }
    return out;
}

void write_pictures(Context& ctx, const geo::Mesh& mesh, const passes::Polycube& p, const std::filesystem::path& dir) {
    passes::RenderOptions view;
    view.width = 800;
    view.height = 800;
    view.smooth = false;
    view.color = passes::MeshColor::Scalar;
    view.scalar_range = std::make_pair(0.0f, 1.0f);
    std::vector<float> face_value(p.surface.face_count());
    for (std::size_t f = 0; f < face_value.size(); ++f)
        face_value[f] = p.hole[f] ? 1.0f : 0.1f + 0.1f * float(p.face_axis[f] / 2);
    const geo::Mesh cube = unshared(p.surface, face_value, view.scalars);
    const geo::RgbaImage picture = passes::render_mesh(ctx, cube, view);
    check_picture_shows_something(picture, "polycube.png");
    geo::write_png(picture, dir / "polycube.png");
    if (p.mapped.empty()) return;

    // The mesh textured through the map: each triangle's checker coordinates are its image's two
    // coordinates across the polycube face it lands on.
    const geo::Bounds box = p.surface.bounds();
    const glm::dvec3 size = box.max - box.min;
    const double extent = std::max({size.x, size.y, size.z});
    geo::Mesh textured;
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 n = glm::cross(p.mapped[t[1]] - p.mapped[t[0]], p.mapped[t[2]] - p.mapped[t[0]]);
        const int axis = passes::axis_of(n) / 2;
        const std::uint32_t base = std::uint32_t(textured.positions.size());
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 q = (p.mapped[t[k]] - box.min) / extent;
            textured.positions.push_back(mesh.positions[t[k]]);
            textured.texcoords.push_back(axis == 0   ? glm::dvec2(q.y, q.z)
                                         : axis == 1 ? glm::dvec2(q.x, q.z)
                                                     : glm::dvec2(q.x, q.y));
        }
        textured.triangles.push_back({base, base + 1, base + 2});
    }
    passes::RenderOptions checker;
    checker.width = 800;
    checker.height = 800;
    checker.color = passes::MeshColor::Checker;
    checker.checker_cells = 16.0;
    checker.smooth = false;
    const geo::RgbaImage picture2 = passes::render_mesh(ctx, textured, checker);
    check_picture_shows_something(picture2, "checker.png");
    geo::write_png(picture2, dir / "checker.png");
}

nlohmann::json statistics_json(const passes::PolycubeStatistics& s) {
    nlohmann::json j;
    j["genus"] = s.genus;
    j["holes"] = s.holes;
    j["saddles"] = s.saddles;
    j["extrema"] = s.extrema;
    j["planes"] = s.planes;
    j["inserted_planes"] = s.inserted_planes;
    j["repair_planes"] = s.repair_planes;
    j["moved_planes"] = s.moved_planes;
    if (!s.repair_note.empty()) j["repair_note"] = s.repair_note;
    j["contours"] = s.contours;
    j["chains"] = s.chains;
    j["closed_by_bezier"] = s.closed_by_bezier;
    j["closed_by_fallback"] = s.closed_by_fallback;
    j["closed_by_chord"] = s.closed_by_chord;
    j["closing_failed"] = s.closing_failed;
    j["quadtree_depth"] = s.quadtree_depth;
    j["mean_excess"] = s.mean_excess;
    j["cells_filled"] = s.cells_filled;
    j["cells_carved"] = s.cells_carved;
    j["cells_opened"] = s.cells_opened;
    j["polycube_faces"] = s.polycube_faces;
    j["polycube_corners"] = s.polycube_corners;
    j["polycube_triangles"] = s.polycube_triangles;
    j["euler_characteristic"] = s.euler_characteristic;
    j["polycube_valid"] = s.polycube_valid;
    if (!s.invalid_reason.empty()) j["invalid_reason"] = s.invalid_reason;
    j["mapped"] = s.mapped;
    if (!s.map_note.empty()) j["map_note"] = s.map_note;
    j["pieces"] = s.pieces;
    j["pieces_mapped"] = s.pieces_mapped;
    j["flips"] = s.flips;
    j["turned_chords"] = s.turned_chords;
    j["boundary_snap"] = s.boundary_snap;
    j["hole_triangles"] = s.hole_triangles;
    j["holes_marked"] = s.holes_marked;
    j["area_distortion"] = s.area_distortion;
    j["angle_distortion"] = s.angle_distortion;
    j["area_distortion_median"] = s.area_distortion_median;
    j["angle_distortion_median"] = s.angle_distortion_median;
    j["area_distortion_unsmoothed"] = s.area_distortion_unsmoothed;
    j["angle_distortion_unsmoothed"] = s.angle_distortion_unsmoothed;
    j["area_distortion_median_unsmoothed"] = s.area_distortion_median_unsmoothed;
    j["angle_distortion_median_unsmoothed"] = s.angle_distortion_median_unsmoothed;
    j["turned_chords_unsmoothed"] = s.turned_chords_unsmoothed;
    j["smoothing_moves"] = s.smoothing_moves;
    j["solves"] = s.solves;
    j["solve_iterations"] = s.solve_iterations;
    j["solve_seconds"] = s.solve_seconds;
    j["seconds"] = s.seconds;
    return j;
}

void run_polycube(const PolycubeCommandOptions& o, const GlobalOptions& global) {
    const geo::Mesh mesh = geo::load_mesh(o.mesh);
    passes::PolycubeOptions po;
    po.dz = o.dz;
    po.da = o.da;
    po.k = o.k;
    po.max_level = o.max_level;
    po.slice_smoothing = o.slice_smoothing;
    po.retry = !o.no_retry;
    po.retry_seconds = o.retry_seconds;
    po.map = !o.no_map;
    po.smoothing = o.smooth;
    po.axis = o.axis == "auto" ? 3 : std::uint8_t(o.axis[0] - 'x');
    std::shared_ptr<Context> ctx = open_context(global);  // the pictures need it even with --cpu
    const auto retrying = [&](const passes::PolycubeStatistics& failed) {
        if (global.quiet) return;
        std::printf(
            "attempt %zu (planes normal to %c, quadtree down to level %u, slice smoothing %u) failed: %s; "
            "trying again\n",
            failed.attempts, char('x' + failed.axis), failed.max_level, failed.slice_smoothing,
            passes::failure_of(failed, po.map).c_str());
        std::fflush(stdout);
    };
    const passes::Polycube p = passes::build_polycube(o.cpu ? nullptr : ctx.get(), mesh, po, retrying);
    const auto& s = p.stats;
    if (global.verbose) std::fprintf(stderr, "%s\n", statistics_json(s).dump(2).c_str());
    const std::string along = s.axes_tried == 3   ? " along z (y and x fail too)"
                              : s.axes_tried == 2 ? " along z (y fails too)"
                                                  : "";
    char spent[160];
    std::snprintf(spent, sizeof spent, "; stopped retrying after %.0f s and %zu attempt%s, past --retry-seconds %g",
                  s.seconds, s.attempts, s.attempts == 1 ? "" : "s", o.retry_seconds);
    const std::string retried = s.retries_cut_short ? spent : s.attempts > s.axes_tried ? ", nor with the retries" : "";
    if (!s.polycube_valid)
        throw geo::InputError("the polycube is not valid" + along + " (" + s.invalid_reason + ")" + retried);
    if (!o.no_map && !s.mapped)
        throw geo::InputError("the map could not be built" + along + ": " + s.map_note + retried +
                              " (--no-map writes the polycube alone)");

    const std::filesystem::path dir(o.out);
    write_polycube_obj(p, dir / "polycube.obj");
    if (!o.no_map) {
        geo::Mesh mapped = mesh;
        mapped.positions = p.mapped;
        mapped.texcoords.clear();
        geo::save_mesh(mapped, dir / "mapped.ply", {.double_precision = true});  // crushed images stay unfolded
    }
    write_pictures(*ctx, mesh, p, dir);
    nlohmann::json j = statistics_json(s);
    j["mesh"] = o.mesh;
    j["vertices"] = mesh.vertex_count();
    j["faces"] = mesh.face_count();
    j["method"] = o.cpu ? "cpu" : "gpu";
    j["dz"] = o.dz;
    j["da"] = o.da;
    j["k"] = o.k;
    j["smooth"] = o.smooth;
    j["axis"] = std::string(1, char('x' + s.axis));
    j["axes_tried"] = s.axes_tried;
    j["attempts"] = s.attempts;
    j["retries_cut_short"] = s.retries_cut_short;
    j["max_level"] = s.max_level;
    j["slice_smoothing"] = s.slice_smoothing;
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
    if (global.quiet) return;
    std::printf(
        "%s: %zu vertices, genus %zu, %zu holes; planes normal to %c%s; %zu saddles, %zu planes (%zu "
        "inserted, %zu repairs)\n",
        o.mesh.c_str(), mesh.vertex_count(), s.genus, s.holes, char('x' + s.axis),
        s.axes_tried == 2   ? " (z failed)"
        : s.axes_tried == 3 ? " (z and y failed)"
                            : "",
        s.saddles, s.planes, s.inserted_planes, s.repair_planes);
    if (s.attempts > s.axes_tried)
        std::printf(
            "built on attempt %zu: quadtree down to level %u, the planes cutting a copy smoothed by %u sweeps\n",
            s.attempts, s.max_level, s.slice_smoothing);
    std::printf(
        "contours %zu, chains %zu closed by Bezier %zu, fallback %zu, chord %zu, failed %zu; quadtree depth %u, "
        "excess %.3f, cells filled %zu, carved %zu, opened %zu\n",
        s.contours, s.chains, s.closed_by_bezier, s.closed_by_fallback, s.closed_by_chord, s.closing_failed,
        s.quadtree_depth, s.mean_excess, s.cells_filled, s.cells_carved, s.cells_opened);
    std::printf("polycube: %zu faces, %zu corners, %zu triangles, chi %lld, valid\n", s.polycube_faces,
                s.polycube_corners, s.polycube_triangles, s.euler_characteristic);
    if (!o.no_map)
        std::printf(
            "map: %zu pieces, %zu flips (%zu chords turned in mapped.ply), boundary snap %.1e, area distortion %.3f "
            "(median %.3f), "
            "angle distortion %.3f (median %.3f), hole triangles %zu (%zu of %zu holes)\n",
            s.pieces, s.flips, s.turned_chords, s.boundary_snap, s.area_distortion, s.area_distortion_median,
            s.angle_distortion, s.angle_distortion_median, s.hole_triangles, s.holes_marked, s.holes);
    if (!o.no_map && o.smooth)
        std::printf(
            "chart smoothing, %u sweeps: chords turned %zu -> %zu, area distortion %.3f (median %.3f) -> %.3f, "
            "angle distortion %.3f (median %.3f) -> %.3f\n",
            o.smooth, s.turned_chords_unsmoothed, s.turned_chords, s.area_distortion_unsmoothed,
            s.area_distortion_median_unsmoothed, s.area_distortion, s.angle_distortion_unsmoothed,
            s.angle_distortion_median_unsmoothed, s.angle_distortion);
    std::printf("time %.2f s (solves %.2f s, %zu solves on the %s)\n", s.seconds, s.solve_seconds, s.solves,
                o.cpu ? "CPU" : "GPU");
    std::printf("wrote %s/{polycube.obj, %spolycube.png}\n", o.out.c_str(),
                o.no_map ? "" : "mapped.ply, checker.png, ");
}

}  // namespace

void add_polycube_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<PolycubeCommandOptions>();
    auto* cmd = app.add_subcommand("polycube", "Closed or open mesh -> polycube and the map onto it");
    cmd->add_option("mesh", o->mesh, "Input mesh: manifold, oriented, one piece; holes allowed (any genus)")
        ->required();
    cmd->add_option("--out", o->out, "Output folder (polycube.obj, mapped.ply, checker.png, polycube.png)")->required();
    add_number_option(cmd, "--dz", o->dz, 0.0, 1e9,
                      "Largest gap between cutting planes (default 0: the bounding box's height / 20)");
    add_number_option(cmd, "--da", o->da, 1e-6, 1e6,
                      "Quadtree stop: (area(p) - area(c)) / area(c) below this (default 0.05)");
    add_count_option(cmd, "--k", o->k, 1, 64, "Parts of each half of the fallback closing polyline (default 2)");
    add_count_option(cmd, "--max-level", o->max_level, 0, 10,
                     "Deepest quadtree level over the model's bounding rectangle (default 8)");
    add_count_option(cmd, "--smooth", o->smooth, 0, 1000,
                     "Sweeps of chart smoothing over the map (default 10; 0: the map as composed)");
    cmd->add_option("--axis", o->axis,
                    "Normal of the cutting planes: x, y, z (the paper's) or auto (default: z, then y, then x while "
                    "the polycube or the map fails)")
        ->check(CLI::IsMember({"x", "y", "z", "auto"}));
    add_count_option(cmd, "--slice-smoothing", o->slice_smoothing, 0, 1000,
                     "Sweeps of umbrella smoothing of the copy of the mesh the planes cut (default 0: the mesh "
                     "itself; the map is still the mesh's)");
    add_number_option(
        cmd, "--retry-seconds", o->retry_seconds, 0.0, 1e6,
        "Start no further attempt (retry or axis) once the attempts took this long, and stop one still running "
        "(default 60; the first attempt runs to its end)");
    cmd->add_flag("--no-retry", o->no_retry,
                  "Fail at once instead of retrying a failed construction on a copy smoothed by 3 sweeps, then with "
                  "the quadtree down to level 10, then with both");
    cmd->add_flag("--cpu", o->cpu, "Solve with the CPU twins");
    cmd->add_flag("--no-map", o->no_map, "Build the polycube only (polycube.obj, polycube.png)");
    cmd->add_option("--json", o->json, "Write the statistics as JSON");
    cmd->callback([o, &global] {
        std::vector<std::string> names{"polycube.obj", "polycube.png"};
        if (!o->no_map) names.insert(names.end(), {"mapped.ply", "checker.png"});
        auto outputs = folder_outputs("--out", o->out, names);
        outputs.push_back(json_output(o->json));
        run_writing({o->mesh}, outputs, [&] {
            make_output_folder("--out", o->out);
            run_polycube(*o, global);
        });
    });
}

}  // namespace gimg::cli

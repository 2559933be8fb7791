// gimg gim MESH --out DIR [--size N] [--variant V] [--corners A,B,C,D] [--iterations N] [--cpu] [--json FILE]
// A disk mesh -> square map (iteratively reweighted) -> N x N geometry image -> mesh, measured.
#include "command_files.h"
#include "commands.h"
#include "gim_report.h"
#include "gpu_context.h"
#include "json_output.h"
#include "progress_line.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/reconstruct.h"
#include "gimg/passes/render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace gimg::cli {

namespace {

struct GimOptions {
    std::string mesh, out, json, view, variant = "curvature", cut_graph = "best";
    std::vector<std::uint32_t> corners;
    std::uint32_t size = 0, picture = 640;
    std::uint64_t iterations = 50, samples = 0, cut_paths = 8;
    double root = 6.0, stop = 0.01;
    bool cpu = false, factors_on_ratio = false, select = false, cut = false;
};

nlohmann::json iteration_json(const passes::IterationReport& r) {
    return {{"iteration", r.iteration},     {"sigma_error", r.sigma_error},
            {"area_spread", r.area_spread}, {"l2_stretch", r.l2_stretch},
            {"flipped", r.flipped},         {"solver_iterations", r.solver_iterations},
            {"seconds", r.seconds},         {"solve_seconds", r.solve_seconds},
            {"image_rms", r.image_rms}};
}

void print_cut(const passes::CutMap& c, const geo::Mesh& input) {
    const passes::DiskCut& cut = c.cut;
    const auto other = cut.graph == geo::CutGraph::FaceTree ? geo::CutGraph::ShortestLoops : geo::CutGraph::FaceTree;
    const bool loops = cut.graph == geo::CutGraph::ShortestLoops;
    std::printf("cut: %zu edges (%.3f diagonals long) from the %s", cut.cut_edges,
                cut.cut_length / input.bounds().diagonal(), geo::cut_graph_name(cut.graph));
    if (c.graph_image_rms.size() == 2)
        std::printf(" (its map's image RMS %.3e, against %.3e from the %s)", c.graph_image_rms[loops],
                    c.graph_image_rms[!loops], geo::cut_graph_name(other));
    else if (cut.graph_l2_stretch.size() == 2)
        std::printf(" (Floater's L2 stretch %.4g, against %.4g from the %s)", cut.graph_l2_stretch[loops],
                    cut.graph_l2_stretch[!loops], geo::cut_graph_name(other));
    std::printf(
        ", %zu stretch paths kept; Floater's L2 stretch %.4f -> %.4f; the disk has %zu vertices (%.2f s); the "
        "seam %s\n",
        cut.paths, cut.l2_stretch.front(), cut.l2_stretch[cut.paths], cut.disk.vertex_count(), c.cut_seconds,
        c.seam ? "is placed for joining" : "stays open");
}

void run_gim(const GimOptions& o, const GlobalOptions& global) {
    passes::geometry_image_size(o.size, 4);  // refuses 1 before the mesh is read
    const geo::Mesh input = geo::load_mesh(o.mesh);
    if (o.cut)
        passes::check_cuttable_mesh(input);
    else
        passes::check_disk_mesh(input);
    const std::uint32_t size = passes::geometry_image_size(o.size, input.vertex_count());
    passes::ParameterizeOptions po;
    po.variant = *passes::parse_variant(o.variant);
    po.max_iterations = o.iterations;
    po.curvature_root = o.root;
    po.stop_fall = o.stop;
    po.boundary_factors_on_ratio = o.factors_on_ratio;
    if (o.select) po.select_size = size;
    if (!o.corners.empty()) {
        if (o.cut)
            throw geo::InputError("--corners and --cut: the cut makes the boundary, so it has no corners to name");
        if (o.corners.size() != 4) throw geo::InputError("--corners takes four boundary vertex indices");
        po.corners = std::array<std::uint32_t, 4>{o.corners[0], o.corners[1], o.corners[2], o.corners[3]};
    }
    std::shared_ptr<Context> ctx = open_context(global);  // the pictures need it even with --cpu
    if (!global.quiet)
        std::printf("%s: %zu vertices, %zu faces; %s map on the %s\n", o.mesh.c_str(), input.vertex_count(),
                    input.face_count(), o.variant.c_str(), o.cpu ? "CPU" : "GPU");
    auto report = [&](const passes::IterationReport& r) {
        if (global.quiet) return;
        std::printf(
            "  iteration %2zu: E_sigma %.3e, area spread %.4f, L2 stretch %.4f, %zu flipped, %zu solver "
            "iterations, %.3f s",
            r.iteration, r.sigma_error, r.area_spread, r.l2_stretch, r.flipped, r.solver_iterations, r.seconds);
        if (o.select) std::printf(", image RMS %.3e", r.image_rms);
        std::printf("\n");
    };
    Context* device = o.cpu ? nullptr : ctx.get();
    std::optional<passes::CutMap> cut;  // with --cut: the cut, its seam's boundary and the map
    if (o.cut) {
        passes::DiskCutOptions co{.max_paths = std::size_t(o.cut_paths)};
        if (o.cut_graph != "best")
            co.graph = o.cut_graph == "face-tree" ? geo::CutGraph::FaceTree : geo::CutGraph::ShortestLoops;
        cut = passes::cut_and_map(device, input, size, po, co);
        if (!global.quiet) print_cut(*cut, input);
        for (const auto& r : cut->map.iterations) report(r);
    }
    // Both sides of every cut path sampled alike, so the reconstruction closes over the seam.
    const std::optional<passes::SeamBoundary>& seam = cut ? cut->seam : std::nullopt;
    const geo::Mesh& mesh = cut ? cut->cut.disk : input;  // what the map takes
    const passes::Parameterization map = cut ? cut->map : passes::parameterize_square(device, mesh, po, report);
    const double cut_seconds = cut ? cut->cut_seconds : 0.0;

    passes::PositionImage image;
    geo::Mesh back;
    const double sample_ms = time_ms([&] {
        image = o.cpu ? passes::geometry_image_cpu(mesh, map.uv, size)
                      : passes::geometry_image_gpu(*ctx, mesh, map.uv, size);
    });
    passes::SeamJoin join;
    const double reconstruct_ms = time_ms([&] {
        join = passes::rebuild_over_seam(image, seam, [&](const passes::PositionImage& im) {
            return o.cpu ? passes::reconstruct_cpu(im, {}) : passes::reconstruct_gpu(*ctx, im, {});
        });
    });
    back = std::move(join.mesh);
    if (seam && !join.joined && !global.quiet)
        std::printf(
            "the seam stays open: joined at %ux%u, the mesh would not be one manifold piece (copies of a cut "
            "vertex on pixels one quad touches)\n",
            size, size);
    if (back.face_count() == 0) throw geo::InputError(o.mesh + ": the geometry image rebuilds no face");
    const std::filesystem::path dir(o.out);
    passes::write_position_exr(image, dir / "gim.exr");
    geo::save_mesh(back, dir / "reconstruction.ply");
    // The map itself: the mesh with (u, v) as texture coordinates, in float64 so that no triangle
    // too small for float32 turns over. gim.exr's pixel (a, b), b the row from the top, samples
    // (u, v) = (a, N - 1 - b) / (N - 1).
    geo::Mesh mapped = mesh;
    mapped.texcoords = map.uv;
    geo::save_mesh(mapped, dir / "param.obj", {.double_precision = true});
    geo::write_png(parameter_picture(*ctx, mesh, map.uv, o.picture), dir / "param.png");
    passes::RenderOptions view;
    view.width = view.height = o.picture;
    view.view = parse_view(o.view);
    geo::RgbaImage picture = passes::render_side_by_side(*ctx, input, back, view);
    check_picture_shows_something(picture, o.mesh);
    for (std::size_t i = 3; i < picture.pixels.size(); i += 4) picture.pixels[i] = 255;
    geo::write_png(picture, dir / "compare.png");

    geo::SurfaceDistanceOptions so;
    if (o.samples) so.sampling.sample_count = o.samples;
    ProgressLine line(global.quiet);
    if (line.on()) so.progress = [&line](double done) { line.percent("surface distance", done); };
    const GimError e = gim_error(input, back, so);
    line.finish();
    std::size_t covered = 0;
    for (auto c : image.covered) covered += c;
    const std::size_t flipped = passes::count_flipped(mesh, map.uv);  // of the map returned
    if (!global.quiet) {
        std::printf(
            "map: %zu iterations (iterate %zu returned) and a final solve of %zu solver iterations, %.2f s, %zu "
            "flipped triangles; %ux%u image (%zu of %zu pixels covered, %.1f ms) -> %zu faces (%.1f ms)\n",
            map.iterations.size() - 1, map.selected, map.final_solver_iterations, map.seconds, flipped, size, size,
            covered, std::size_t(size) * size, sample_ms, back.face_count(), reconstruct_ms);
        const std::size_t stopped = map.rule_iteration;
        if (cut && !o.select && map.selected != stopped)
            std::printf(
                "note: iterate %zu (%s) rebuilds the cut surface better (image RMS %.3e) than iterate %zu, "
                "where the run stopped (%.3e), and is returned\n",
                map.selected, map.selected == 0 ? "Floater's start" : "the least E_sigma",
                map.iterations[map.selected].image_rms, stopped, map.iterations[stopped].image_rms);
        if (!map.unsolved.empty())
            std::printf("note: the run ended where a reweighted system could not be solved (%s)\n",
                        map.unsolved.c_str());
        std::printf(
            "relative to the bounding-box diagonal: RMS %.3e (original->reconstruction %.3e, back %.3e), "
            "Hausdorff %.3e, PSNR %.2f dB\n",
            e.rms, e.distance.a_to_b.rms / e.distance.bbox_diagonal, e.distance.b_to_a.rms / e.distance.bbox_diagonal,
            e.hausdorff, e.psnr);
        std::printf("wrote %s/{gim.exr, reconstruction.ply, param.obj, param.png, compare.png}\n", o.out.c_str());
    }
    nlohmann::json iterations = nlohmann::json::array();
    for (const auto& r : map.iterations) iterations.push_back(iteration_json(r));
    nlohmann::json j{{"mesh", o.mesh},
                     {"vertices", input.vertex_count()},
                     {"faces", input.face_count()},
                     {"variant", o.variant},
                     {"method", o.cpu ? "cpu" : "gpu"},
                     {"size", size},
                     {"corners", map.boundary.corners},
                     {"iterations", iterations},
                     {"selected_iteration", map.selected},
                     {"rule_iteration", map.rule_iteration},
                     {"final_solver_iterations", map.final_solver_iterations},
                     {"unsolved", map.unsolved.empty() ? nlohmann::json(nullptr) : nlohmann::json(map.unsolved)},
                     {"map_seconds", map.seconds},
                     {"solve_seconds", map.solve_seconds},
                     {"map_submissions", map.submissions},
                     {"map_device_wait_seconds", map.device_wait_seconds},
                     {"flipped", flipped},
                     {"covered_pixels", covered},
                     {"sample_ms", sample_ms},
                     {"reconstruct_ms", reconstruct_ms},
                     {"reconstruction_faces", back.face_count()},
                     {"error", gim_error_json(e)}};
    if (cut)
        j["cut"] = {{"edges", cut->cut.cut_edges},
                    {"length", cut->cut.cut_length / input.bounds().diagonal()},
                    {"graph", geo::cut_graph_name(cut->cut.graph)},
                    {"tried", cut->cut.tried},
                    {"graph_l2_stretch", cut->cut.graph_l2_stretch},
                    {"graph_image_rms", cut->graph_image_rms},
                    {"paths", cut->cut.paths},
                    {"l2_stretch", cut->cut.l2_stretch},
                    {"split_edges", cut->cut.split_edges},
                    {"seam_joined", join.joined},
                    {"joined_pixels", join.joined_pixels},
                    {"merged_vertices", join.merged_vertices},
                    {"disk_vertices", cut->cut.disk.vertex_count()},
                    {"seconds", cut_seconds}};
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

}  // namespace

void add_gim_command(CLI::App& app, const GlobalOptions& global) {
    auto o = std::make_shared<GimOptions>();
    auto* cmd = app.add_subcommand("gim", "Disk mesh -> square parameterization -> geometry image -> mesh, measured");
    cmd->add_option("mesh", o->mesh, "Input mesh: one component, manifold, one boundary loop (any, with --cut)")
        ->required();
    cmd->add_option("--out", o->out, "Output folder (gim.exr, reconstruction.ply, param.obj, param.png, compare.png)")
        ->required();
    add_count_option(cmd, "--size", o->size, 0, 16384, "Image size N (N x N; 0, the default: round(sqrt(vertices)))");
    cmd->add_option("--variant", o->variant,
                    "tutte, floater, stretch (Yoshizawa et al. 2004), density, uniform3d or curvature (default)")
        ->check(CLI::IsMember({"tutte", "floater", "stretch", "density", "uniform3d", "curvature"}));
    cmd->add_option("--corners", o->corners,
                    "Four boundary vertex indices, in boundary order, for the square's corners (default: at quarter "
                    "arc lengths)")
        ->delimiter(',')
        ->expected(4);
    add_count_option(cmd, "--iterations", o->iterations, 1, 1000, "Most reweighting iterations (default 50)");
    add_number_option(cmd, "--stop", o->stop, 0.0, 1.0,
                      "Stop when E_sigma (stretch: the L2 stretch) falls by less than this fraction (default 0.01)");
    add_number_option(cmd, "--root", o->root, 1.0, 16.0,
                      "N in the curvature measure (k1^2 + k2^2)^(1/N) (default 6; the thesis: 3 to 4)");
    cmd->add_flag("--factors-on-ratio", o->factors_on_ratio,
                  "Apply the corner x4 and boundary x2 factors to uniform3d's and curvature's ratios too (as printed)");
    add_count_option(cmd, "--picture", o->picture, 64, 4096,
                     "Side of param.png, and of each half of compare.png, in pixels (default 640)");
    cmd->add_option("--view", o->view, "compare.png's camera azimuth and elevation in degrees, AZ,EL (default 35,20)");
    cmd->add_flag("--select", o->select,
                  "Return the iterate whose N x N image rebuilds the mesh best (measured on the CPU, 50,000 "
                  "samples each way), not the last");
    cmd->add_flag("--cut", o->cut,
                  "Cut the mesh open into a disk first (any genus, any number of holes): a cut graph or a seam, and "
                  "paths toward the stretch of Floater's map");
    cmd->add_option("--cut-graph", o->cut_graph,
                    "With --cut: the initial cut graph, face-tree (Gu et al.'s), shortest-loops (Erickson and "
                    "Whittlesey's) or best (the default: both tried, the one of lower stretch kept)")
        ->check(CLI::IsMember({"best", "face-tree", "shortest-loops"}));
    add_count_option(cmd, "--cut-paths", o->cut_paths, 0, 1000,
                     "With --cut: most paths added toward the stretch (default 8)");
    cmd->add_flag("--cpu", o->cpu, "Solve and sample with the CPU twins instead of the GPU");
    add_count_option(cmd, "--samples", o->samples, 1, 100'000'000,
                     "Surface samples per mesh for the distance (default max(1M, 10 per face))");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] {
        auto outputs =
            folder_outputs("--out", o->out, {"gim.exr", "reconstruction.ply", "param.obj", "param.png", "compare.png"});
        outputs.push_back(json_output(o->json));
        run_writing({o->mesh}, outputs, [&] {
            parse_view(o->view);  // refused before any work
            make_output_folder("--out", o->out);
            run_gim(*o, global);
        });
    });
}

}  // namespace gimg::cli

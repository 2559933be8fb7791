// gimg render MESH --out IMG.png [--size WxH] [--view AZ,EL] [--wireframe]
//             [--color plain|normal|curvature|checker|scalar FILE] [--compare OTHER_MESH] [--flat]
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "size_option.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/curvature.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/image.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/render.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

namespace gimg::cli {

namespace {

struct RenderCliOptions {
    std::string mesh, out, size = "1024x768", view, compare, json;
    std::vector<std::string> color{"plain"};
    bool wireframe = false, flat = false;
};

// One float per vertex, separated by whitespace or newlines.
std::vector<float> read_scalars(const std::string& path, std::size_t expected) {
    std::ifstream in(path);
    if (!in) throw geo::InputError("cannot read scalar file " + path);
    std::vector<float> values;
    std::string token;
    while (in >> token) {
        char* end = nullptr;
        const float v = std::strtof(token.c_str(), &end);
        if (end == token.c_str() || *end != '\0' || !std::isfinite(v))
            throw geo::InputError(path + ": '" + token + "' is not a finite number (value " +
                                  std::to_string(values.size() + 1) + ")");
        values.push_back(v);
        if (values.size() > expected) break;
    }
    if (values.size() != expected)
        throw geo::InputError(path + " holds " + std::string(values.size() > expected ? "more than " : "") +
                              std::to_string(values.size()) + " values; the mesh has " + std::to_string(expected) +
                              " vertices");
    return values;
}

void run_render(const RenderCliOptions& o, const GlobalOptions& global) {
    const auto start = std::chrono::steady_clock::now();
    passes::RenderOptions r;
    const auto size = parse_size(o.size, 8192);
    r.width = size[0];
    r.height = size[1];
    r.view = parse_view(o.view);
    r.wireframe = o.wireframe;
    r.smooth = !o.flat;
    const geo::Mesh mesh = geo::load_mesh(o.mesh);

    const std::string& mode = o.color.front();
    if (mode == "scalar" && o.color.size() != 2)
        throw geo::InputError("--color scalar needs a file: --color scalar FILE");
    if (mode != "scalar" && o.color.size() != 1) throw geo::InputError("--color " + mode + " takes no file");
    if (mode == "normal") r.color = passes::MeshColor::Normal;
    if (mode == "checker") r.color = passes::MeshColor::Checker;
    if (mode == "scalar") {
        r.color = passes::MeshColor::Scalar;
        r.scalars = read_scalars(o.color[1], mesh.vertex_count());
    }
    if (mode == "curvature") {
        // Signed mean curvature on a diverging map: blue concave, red convex.
        r.color = passes::MeshColor::Diverging;
        const geo::VertexCurvature k = geo::compute_curvature(mesh, geo::build_adjacency(mesh));
        r.scalars.assign(k.mean.begin(), k.mean.end());
    }

    auto ctx = open_context(global);
    geo::RgbaImage image;
    if (o.compare.empty()) {
        image = passes::render_mesh(*ctx, mesh, r);
    } else {
        const geo::Mesh other = geo::load_mesh(o.compare);
        image = passes::render_side_by_side(*ctx, mesh, other, r);
    }
    check_picture_shows_something(image, o.mesh);
    // Opaque PNG: the colour is already blended over the background.
    for (std::size_t i = 3; i < image.pixels.size(); i += 4) image.pixels[i] = 255;
    geo::write_png(image, o.out);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!global.quiet)
        std::printf("%s: %zu faces -> %s (%ux%u, %s) in %.3f s\n", o.mesh.c_str(), mesh.face_count(), o.out.c_str(),
                    image.width, image.height, mode.c_str(), seconds);
    nlohmann::json j{{"mesh", o.mesh},         {"out", o.out},  {"width", image.width},
                     {"height", image.height}, {"color", mode}, {"seconds", seconds}};
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

}  // namespace

void add_render_command(CLI::App& app, const GlobalOptions& global) {
    auto opts = std::make_shared<RenderCliOptions>();
    auto* cmd = app.add_subcommand("render", "Render a mesh headlessly to a PNG");
    cmd->add_option("mesh", opts->mesh, "Mesh to render (OBJ, PLY, OFF, STL)")->required();
    cmd->add_option("--out", opts->out, "Output PNG")->required();
    cmd->add_option("--size", opts->size, "Picture size WxH (default 1024x768)");
    cmd->add_option("--view", opts->view, "Camera azimuth and elevation in degrees, AZ,EL (default 35,20)");
    cmd->add_flag("--wireframe", opts->wireframe, "Draw the edges over the surface");
    cmd->add_flag("--flat", opts->flat, "One normal per face (facets visible) instead of smooth shading");
    cmd->add_option("--color", opts->color,
                    "plain, normal, curvature (signed mean), checker, or scalar FILE "
                    "(one value per vertex)")
        ->expected(1, 2);
    cmd->add_option("--compare", opts->compare, "A second mesh drawn beside the first with the same camera");
    cmd->add_option("--json", opts->json, "Write the figures as JSON");
    cmd->callback([opts, &global] {
        static const std::set<std::string> modes{"plain", "normal", "curvature", "checker", "scalar"};
        if (!modes.count(opts->color.front()))
            throw geo::InputError("--color must be plain, normal, curvature, checker or scalar FILE, got '" +
                                  opts->color.front() + "'");
        run_writing({opts->mesh, opts->compare, opts->color.size() == 2 ? opts->color[1] : std::string()},
                    {{"--out", opts->out, {".png"}}, json_output(opts->json)}, [&] { run_render(*opts, global); });
    });
}

}  // namespace gimg::cli

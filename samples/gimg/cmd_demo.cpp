// gimg demo: every capability on a shape built in code (no mesh files needed): a lumpy sphere is
// rendered, projected into a cylindrical geometry image on the GPU (checked against the CPU ray
// caster), reconstructed from it on the GPU (measured against the model), cast as a hierarchical
// image, and mapped conformally onto the sphere; demo-output/index.html shows the pictures and the
// key figures.
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "timing.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/image.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/cylinder_hierarchy.h"
#include "gimg/passes/reconstruct.h"
#include "gimg/passes/render.h"
#include "gimg/passes/sphere.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace gimg::cli {

namespace {

// An icosphere pushed in and out by a few waves: concave parts, so the image has occlusions.
geo::Mesh lumpy_sphere() {
    geo::Mesh m = geo::make_icosphere(1.0, 6);
    for (auto& p : m.positions) {
        const glm::dvec3 n = glm::normalize(p);
        const double bump = 0.18 * std::sin(5.0 * n.x) * std::sin(4.0 * n.y + 1.0) * std::sin(3.0 * n.z + 0.5) +
                            0.25 * std::exp(-8.0 * glm::dot(n - glm::dvec3(0, 0.6, 0.8), n - glm::dvec3(0, 0.6, 0.8)));
        p = n * (1.0 + bump);
        p.y *= 1.6;  // taller than wide, like most things people scan
    }
    return m;
}

std::string figure(const char* format, double a, double b = 0.0, double c = 0.0) {
    char text[256];
    std::snprintf(text, sizeof text, format, a, b, c);
    return text;
}

// One page with the pictures and the figures, for a browser.
std::string index_html(const std::string& device, const std::string& cylinder, const std::string& reconstruction,
                       const std::string& hierarchy, const std::string& sphere) {
    auto section = [](const std::string& title, const std::string& text, const std::string& pictures) {
        return "<h2>" + title + "</h2>\n<p>" + text + "</p>\n<p>" + pictures + "</p>\n";
    };
    auto img = [](const std::string& file, const std::string& alt) {
        return "<img src=\"" + file + "\" alt=\"" + alt + "\" width=\"400\"> ";
    };
    return "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>gimg demo</title>"
           "<style>body{font-family:sans-serif;max-width:900px;margin:2em auto}img{border:1px solid #ccc}</style>"
           "</head><body>\n<h1>gimg demo</h1>\n<p>A lumpy sphere of 81,920 faces built in code, on " +
           device + ".</p>\n" +
           section("The model", "Rendered by the headless renderer (colour = normal).", img("model.png", "the model")) +
           section("Cylindrical geometry image", cylinder, img("distance.png", "cylindrical geometry image")) +
           section("Reconstruction from the image", reconstruction,
                   img("reconstruction.png", "the reconstructed mesh")) +
           section("Hierarchical cylindrical image", hierarchy,
                   img("hierarchical.png", "the mesh rebuilt from the hierarchical image")) +
           section("Conformal map onto the sphere", sphere,
                   img("checker.png", "the model textured through its spherical map") +
                       img("sphere.png", "the sphere mesh")) +
           "</body></html>\n";
}

void run_demo(const std::string& out, const GlobalOptions& global) {
    auto ctx = open_context(global);
    const geo::Mesh mesh = lumpy_sphere();
    const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
    const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, frame);
    const std::uint32_t W = 512, H = 256;

    passes::CylinderZBuffer zbuffer(*ctx, W, H, {.timestamps = true});
    const std::uint32_t id = zbuffer.add_mesh(cyl);
    zbuffer.project(id);  // first use compiles the pipelines
    passes::CylinderImage gpu;
    const double gpu_wall = time_ms([&] { gpu = zbuffer.project(id); });
    passes::CylinderImage cpu;
    const double cpu_wall = time_ms([&] { cpu = passes::cylinder_raycast(cyl, W, H); });
    std::size_t covered = 0, differ = 0;
    for (std::size_t i = 0; i < gpu.covered.size(); ++i) {
        covered += gpu.covered[i];
        differ +=
            gpu.covered[i] != cpu.covered[i] || (gpu.covered[i] && std::abs(gpu.distance[i] - cpu.distance[i]) > 1e-5f);
    }

    passes::write_cylinder_files(out, gpu, frame, {"demo: lumpy sphere", "zbuffer"});
    passes::RenderOptions view;
    view.width = 640;
    view.height = 640;
    view.view = {30.0, 15.0, 30.0};
    view.color = passes::MeshColor::Normal;
    geo::RgbaImage picture = passes::render_mesh(*ctx, mesh, view);
    for (std::size_t i = 3; i < picture.pixels.size(); i += 4) picture.pixels[i] = 255;
    geo::write_png(picture, std::filesystem::path(out) / "model.png");

    if (differ != 0) throw std::runtime_error("the GPU image differs from the CPU ray caster");

    // The image back to a mesh on the GPU, and how far it lies from the model.
    passes::ReconstructStats rstats;
    geo::Mesh rebuilt = passes::reconstruct_gpu(*ctx, gpu, frame);  // first use compiles the pipelines
    const double rebuild_ms = time_ms([&] { rebuilt = passes::reconstruct_gpu(*ctx, gpu, frame, {}, &rstats); });
    geo::save_mesh(rebuilt, std::filesystem::path(out) / "reconstruction.ply");
    const geo::SurfaceDistance error = geo::surface_distance(rebuilt, mesh);
    const double diagonal = mesh.bounds().diagonal();
    geo::RgbaImage rebuilt_picture = passes::render_mesh(*ctx, rebuilt, view);
    for (std::size_t i = 3; i < rebuilt_picture.pixels.size(); i += 4) rebuilt_picture.pixels[i] = 255;
    geo::write_png(rebuilt_picture, std::filesystem::path(out) / "reconstruction.png");

    // The hierarchical image (the thesis's chapter 3) from 32 x 32 to 256 x 256: rays on the GPU,
    // checked against the CPU encoder, decoded on the GPU.
    const passes::CylinderHierarchyOptions hopt{.base = 32, .size = 256};
    passes::CylinderHierarchy hierarchy = passes::cylinder_hierarchy_gpu(*ctx, cyl, hopt);  // as above
    const double hier_gpu_ms = time_ms([&] { hierarchy = passes::cylinder_hierarchy_gpu(*ctx, cyl, hopt); });
    passes::CylinderHierarchy hierarchy_cpu;
    const double hier_cpu_ms = time_ms([&] { hierarchy_cpu = passes::cylinder_hierarchy_cpu(cyl, hopt); });
    if (hierarchy.t != hierarchy_cpu.t || hierarchy.valid != hierarchy_cpu.valid)
        throw std::runtime_error("the GPU hierarchy differs from the CPU encoder's");
    const geo::Mesh hier_mesh =
        passes::hierarchy_mesh(passes::decode_cylinder_hierarchy_gpu(*ctx, hierarchy, hierarchy.levels()), frame);
    const geo::SurfaceDistance hier_error = geo::surface_distance(mesh, hier_mesh);
    geo::RgbaImage hier_picture = passes::render_mesh(*ctx, hier_mesh, view);
    for (std::size_t i = 3; i < hier_picture.pixels.size(); i += 4) hier_picture.pixels[i] = 255;
    geo::write_png(hier_picture, std::filesystem::path(out) / "hierarchical.png");

    // The conformal spherical map by the default method.
    passes::SphereResult map;
    const double sphere_ms = time_ms([&] { map = passes::sphere_harmonic(*ctx, mesh); });
    const passes::SphereMetrics quality = passes::sphere_metrics(mesh, map.positions);
    write_sphere_pictures(*ctx, mesh, map.positions, out);

    const std::string cylinder_text =
        figure("%.0fx%.0f pixels by the GPU cylindrical Z-buffer in %.2f ms (wall), ", W, H, gpu_wall) +
        figure("the CPU ray caster in %.2f ms; %.0f pixels covered, ", cpu_wall, double(covered)) +
        figure("%.0f differ. Brightness is the distance from the axis.", double(differ));
    const std::string rebuild_text =
        figure("%.0f vertices and %.0f triangles in %.2f ms on the GPU; ", double(rebuilt.vertex_count()),
               double(rebuilt.face_count()), rebuild_ms) +
        figure("reconstruction to model: mean %.2e, RMS %.2e, max %.2e of the bounding-box diagonal.",
               error.a_to_b.mean / diagonal, error.a_to_b.rms / diagonal, error.a_to_b.max / diagonal);
    const std::string sphere_text =
        figure("%.0f vertices in %.2f s by the harmonic method; ", double(mesh.vertex_count()), sphere_ms / 1000.0) +
        figure("%.0f flipped triangles, conformal energy %.5f of 8 pi, ", double(quality.flips),
               quality.conformal_ratio) +
        figure("angle distortion mean %.2f, p95 %.2f degrees.", quality.angle_distortion_deg.mean,
               quality.angle_distortion_deg.p95);
    const std::string hierarchy_text =
        figure("%.0f levels from 32x32 to 256x256: %.0f ms with the rays on the GPU, ", double(hierarchy.levels()),
               hier_gpu_ms) +
        figure("%.0f ms on the CPU (the same image); model to reconstruction RMS %.2e of the diagonal, ", hier_cpu_ms,
               hier_error.a_to_b.rms / diagonal) +
        figure("back %.2e.", hier_error.b_to_a.rms / diagonal);
    geo::write_file_atomically(
        std::filesystem::path(out) / "index.html",
        index_html(ctx->device_info().summary(), cylinder_text, rebuild_text, hierarchy_text, sphere_text));

    if (!global.quiet) {
        std::printf("gimg demo: a %zu-face model built in code\n", mesh.face_count());
        std::printf("device: %s\n", ctx->device_info().summary().c_str());
        std::printf("cylindrical image: %s\n", cylinder_text.c_str());
        std::printf("reconstruction: %s\n", rebuild_text.c_str());
        std::printf("hierarchical image: %s\n", hierarchy_text.c_str());
        std::printf("spherical map: %s\n", sphere_text.c_str());
        std::printf("wrote %s/index.html (open it in a browser) and the files it shows\n", out.c_str());
    }
}

}  // namespace

void add_demo_command(CLI::App& app, const GlobalOptions& global) {
    auto out = std::make_shared<std::string>("demo-output");
    auto* cmd = app.add_subcommand("demo", "Every capability on a model built in code; writes demo-output/index.html");
    cmd->add_option("--out", *out, "Output folder (default demo-output)");
    cmd->callback([out, &global] {
        run_writing(
            {},
            folder_outputs("--out", *out,
                           {"distance.exr", "distance.png", "frame.json", "model.png", "reconstruction.ply",
                            "reconstruction.png", "hierarchical.png", "checker.png", "sphere.png", "index.html"}),
            [&] { run_demo(*out, global); });
    });
}

}  // namespace gimg::cli

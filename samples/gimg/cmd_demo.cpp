// gimg demo: the headline on a shape built in code (no mesh files needed): a lumpy sphere is
// rendered, projected into a cylindrical geometry image on the GPU, checked against the CPU ray
// caster, and written out for people to look at.
#include "commands.h"
#include "gpu_context.h"
#include "timing.h"

#include "gimg/geometry/image.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/render.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>

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
        differ += gpu.covered[i] != cpu.covered[i] || (gpu.covered[i] && std::abs(gpu.distance[i] - cpu.distance[i]) > 1e-5f);
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

    if (!global.quiet) {
        std::printf("gimg demo: a %zu-face model built in code -> a %ux%u cylindrical geometry image\n",
                    mesh.face_count(), W, H);
        std::printf("device: %s\n", ctx->device_info().summary().c_str());
        std::printf("GPU cylindrical z-buffer: %.2f ms GPU, %.2f ms wall; CPU ray caster: %.2f ms; %zu pixels covered, "
                    "%zu differ\n", zbuffer.last_gpu_ms(), gpu_wall, cpu_wall, covered, differ);
        std::printf("wrote %s/{model.png, distance.png, distance.exr, frame.json}\n", out.c_str());
    }
    if (differ != 0) throw std::runtime_error("the GPU image differs from the CPU ray caster");
}

}  // namespace

void add_demo_command(CLI::App& app, const GlobalOptions& global) {
    auto out = std::make_shared<std::string>("demo-output");
    auto* cmd = app.add_subcommand("demo", "Project a model built in code into a cylindrical geometry image");
    cmd->add_option("--out", *out, "Output folder (default demo-output)");
    cmd->callback([out, &global] { run_demo(*out, global); });
}

}  // namespace gimg::cli

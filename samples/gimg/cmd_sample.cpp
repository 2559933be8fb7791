// gimg sample MESH --size N --out GI.exr [--cpu] [--json FILE]
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/geometry/io.h"
#include "gimg/passes/sample.h"

#include <cstdio>

namespace gimg::cli {

void add_sample_command(CLI::App& app, const GlobalOptions& global) {
    struct Options {
        std::string mesh, out, json;
        std::uint32_t size = 256;
        bool cpu = false;
    };
    auto o = std::make_shared<Options>();
    auto* cmd = app.add_subcommand("sample", "Sample a mesh with texture coordinates into a position geometry image");
    cmd->add_option("mesh", o->mesh, "Mesh whose file carries per-vertex texture coordinates")->required();
    add_count_option(cmd, "--size", o->size, 2, 16384, "Image size N (N x N; default 256)");
    cmd->add_option("--out", o->out, "Output EXR (channels R, G, B = x, y, z and A = covered)")->required();
    cmd->add_flag("--cpu", o->cpu, "Use the CPU reference instead of the GPU pass");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] {
        check_command_files({o->mesh}, {{"--out", o->out, {".exr"}}, json_output(o->json)});
        geo::OutputSet files;
        const geo::Mesh mesh = geo::load_mesh(o->mesh);
        std::shared_ptr<Context> ctx;
        if (!o->cpu) ctx = open_context(global);
        passes::PositionImage image;
        const double ms = time_ms(
            [&] { image = o->cpu ? passes::sample_cpu(mesh, o->size) : passes::sample_gpu(*ctx, mesh, o->size); });
        passes::write_position_exr(image, o->out);
        std::size_t covered = 0;
        for (auto c : image.covered) covered += c;
        if (!global.quiet)
            std::printf("%s: %zu faces -> %ux%u position image, %zu pixels covered, %.2f ms; wrote %s\n",
                        o->mesh.c_str(), mesh.face_count(), o->size, o->size, covered, ms, o->out.c_str());
        nlohmann::json j{{"mesh", o->mesh},
                         {"out", o->out},
                         {"size", o->size},
                         {"covered_pixels", covered},
                         {"method", o->cpu ? "cpu" : "gpu"},
                         {"seconds", ms / 1000.0}};
        add_machine_figures(j, ctx.get());
        write_json(o->json, j);
        files.commit();
    });
}

}  // namespace gimg::cli

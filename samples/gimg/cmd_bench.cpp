// gimg bench cylinder [--mesh PATH]... [--size WxH|auto]... [--runs N] [--batch-images N] [--json FILE]
//
// The three cylindrical methods (and Embree, when built with it) on the same meshes in one
// process: medians of N runs of GPU time (timestamps) and wall time per projection, the time for a
// new mesh (upload or BVH build plus one image), ratios, and batch throughput.
#include "bench_paths.h"
#include "command_files.h"
#include "commands.h"
#include "embree_peer.h"
#include "gpu_context.h"
#include "json_output.h"
#include "size_option.h"
#include "timing.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/reconstruct.h"

#include <glm/ext/matrix_transform.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace gimg::cli {

namespace {

struct BenchOptions {
    std::vector<std::string> meshes, sizes{"auto", "540x270"}, batch_meshes;
    std::uint32_t runs = 5;
    std::uint32_t batch_images = 256;
    std::uint32_t small_pixels = passes::CylinderZBufferOptions{}.small_pixels;
    std::string large_pieces = "auto";
    std::string json;

    passes::CylinderZBufferOptions zbuffer(bool timestamps = false) const {
        const auto large = large_pieces == "graphics"  ? passes::CylinderLargePieces::Graphics
                           : large_pieces == "compute" ? passes::CylinderLargePieces::Compute
                                                       : passes::CylinderLargePieces::Auto;
        return {.small_pixels = small_pixels, .large_pieces = large, .timestamps = timestamps};
    }
};

// The default set: armadillo and bunny from ../shared/meshes, the fetched large ones.
std::vector<std::string> default_meshes() {
    const auto shared = shared_mesh_dir();
    const auto large = large_mesh_dir();
    std::vector<std::string> out;
    for (const auto& p :
         {shared / "armadillo.off", shared / "bunny.off", large / "derived/bunny_loop1.off", large / "dragon.ply"}) {
        if (std::filesystem::exists(p))
            out.push_back(p.string());
        else
            std::fprintf(
                stderr, "gimg bench: skipping %s (not found; ../shared/meshes/fetch_large.sh fetches the large ones)\n",
                p.c_str());
    }
    return out;
}

std::vector<std::string> default_batch_meshes() {
    const auto shared = shared_mesh_dir();
    std::vector<std::string> out;
    for (const char* name : {"homer.off", "dragon_res4.ply", "mech_holes_shark.off"})
        if (std::filesystem::exists(shared / name)) out.push_back((shared / name).string());
    return out;
}

passes::CylinderTransform rotation(double degrees_y, double degrees_z) {
    // Spin about the axis and tilt about z through the cylinder's centre.
    const glm::dmat4 m = glm::translate(glm::dmat4(1.0), {0, 0.5, 0}) *
                         glm::rotate(glm::dmat4(1.0), glm::radians(degrees_z), {0, 0, 1}) *
                         glm::rotate(glm::dmat4(1.0), glm::radians(degrees_y), {0, 1, 0}) *
                         glm::translate(glm::dmat4(1.0), {0, -0.5, 0});
    return passes::to_cylinder_transform(m);
}

struct Row {
    std::string mesh;
    std::size_t faces;
    std::uint32_t width, height;
    double zbuffer_gpu_ms, zbuffer_ms, zbuffer_new_mesh_ms;
    double zbuffer_graphics_only_ms;  // every piece through the graphics pipeline
    double raycast_bvh_ms, raycast_ms, scanline_ms, scanline_1t_ms;
    double embree_bvh_ms = 0.0, embree_ms = 0.0;
};

Row bench_one(Context& ctx, const std::string& path, const geo::Mesh& mesh, const passes::CylinderMesh& cyl,
              std::uint32_t w, std::uint32_t h, int runs, const BenchOptions& o) {
    Row r{std::filesystem::path(path).filename().string(), mesh.face_count(), w, h, 0, 0, 0, 0, 0, 0, 0, 0};
    std::vector<double> gpu, wall, fresh, graphics_only, bvh, ray, scan, scan1, ebvh, eray;
    passes::CylinderZBuffer all_graphics(ctx, w, h,
                                         {.small_pixels = 0, .large_pieces = passes::CylinderLargePieces::Graphics});
    all_graphics.add_mesh(cyl);
    // GPU time from a timestamped twin: the wall-clock runs go without timestamps, which cost
    // lavapipe 0.2-0.5 ms a projection.
    passes::CylinderZBuffer timed(ctx, w, h, o.zbuffer(true));
    timed.add_mesh(cyl);
    {
        passes::CylinderZBuffer warm(ctx, w, h, o.zbuffer());  // pipelines compile once per process
        warm.project(warm.add_mesh(cyl));
        all_graphics.project(0);
        timed.project(0);
    }
    for (int k = 0; k < runs; ++k) {
        std::unique_ptr<passes::CylinderZBuffer> z;
        fresh.push_back(time_ms([&] {
            z = std::make_unique<passes::CylinderZBuffer>(ctx, w, h, o.zbuffer());
            z->project(z->add_mesh(cyl));
        }));
        wall.push_back(time_ms([&] { z->project(0); }));
        timed.project(0);
        gpu.push_back(timed.last_gpu_ms());
        graphics_only.push_back(time_ms([&] { all_graphics.project(0); }));
        std::unique_ptr<passes::CylinderRaycaster> caster;
        bvh.push_back(time_ms([&] { caster = std::make_unique<passes::CylinderRaycaster>(cyl); }));
        ray.push_back(time_ms([&] { caster->project(w, h); }));
        scan.push_back(time_ms([&] { passes::cylinder_scanline(cyl, w, h); }));
        scan1.push_back(time_ms([&] { passes::cylinder_scanline(cyl, w, h, passes::kIdentityTransform, 1); }));
        if (embree_available()) {
            std::unique_ptr<EmbreeCylinderCaster> e;
            ebvh.push_back(time_ms([&] { e = std::make_unique<EmbreeCylinderCaster>(cyl); }));
            eray.push_back(time_ms([&] { e->project(w, h); }));
        }
    }
    r.zbuffer_gpu_ms = median(gpu);
    r.zbuffer_ms = median(wall);
    r.zbuffer_new_mesh_ms = median(fresh);
    r.zbuffer_graphics_only_ms = median(graphics_only);
    r.raycast_bvh_ms = median(bvh);
    r.raycast_ms = median(ray);
    r.scanline_ms = median(scan);
    r.scanline_1t_ms = median(scan1);
    r.embree_bvh_ms = median(ebvh);
    r.embree_ms = median(eray);
    return r;
}

void run_bench(const BenchOptions& o, const GlobalOptions& global) {
    auto ctx = open_context(global);
    const int runs = int(o.runs);
    nlohmann::json j;
    j["device"] = ctx->device_info().name;
    j["runs"] = runs;
    j["embree"] = embree_available();
    j["small_pixels"] = o.small_pixels;
    const bool graphics = passes::CylinderZBuffer(*ctx, 1, 1, o.zbuffer()).graphics_pipeline();
    // No GPU time on CPU devices: lavapipe runs on the same cores, so the wall times are its measure.
    const bool gpu_times = ctx->device_info().type != VK_PHYSICAL_DEVICE_TYPE_CPU;
    j["large_pieces"] = graphics ? "graphics" : "compute";
    std::printf(
        "gimg bench cylinder on %s; medians of %d runs; times in ms; zbuffer: pieces of <= %u pixels in the "
        "classify pass, larger ones %s\n",
        ctx->device_info().summary().c_str(), runs, o.small_pixels,
        graphics ? "through the graphics pipeline" : "in the large-piece compute pass");
    std::printf("%-22s %8s %9s | %9s %9s %9s %9s | %9s %9s | %9s %9s | %9s %9s | %7s %7s %7s\n", "mesh", "faces",
                "size", "zbuf GPU", "zbuf wall", "zbuf new", "gfx only", "ray BVH", "ray img", "scan", "scan 1t",
                "embree BVH", "embree img", "ray/zb", "scan/zb", "emb/zb");
    for (const std::string& path : o.meshes.empty() ? default_meshes() : o.meshes) {
        const geo::Mesh mesh = geo::load_mesh(path);
        const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, passes::fit_cylinder_frame(mesh));
        for (const std::string& size_text : o.sizes) {
            const auto size =
                size_text == "auto" ? passes::auto_cylinder_size(mesh.face_count()) : parse_size(size_text);
            const Row r = bench_one(*ctx, path, mesh, cyl, size[0], size[1], runs, o);
            const double zb = r.zbuffer_ms;
            char embree[64] = "        -         - ";
            char embree_ratio[16] = "      -";
            if (embree_available()) {
                std::snprintf(embree, sizeof embree, "%9.2f %9.2f", r.embree_bvh_ms, r.embree_ms);
                std::snprintf(embree_ratio, sizeof embree_ratio, "%7.2f", r.embree_ms / zb);
            }
            char gpu_ms[16] = "        -";
            if (gpu_times) std::snprintf(gpu_ms, sizeof gpu_ms, "%9.2f", r.zbuffer_gpu_ms);
            std::printf(
                "%-22s %8zu %4ux%-4u | %s %9.2f %9.2f %9.2f | %9.2f %9.2f | %9.2f %9.2f | %s | %7.2f %7.2f %s\n",
                r.mesh.c_str(), r.faces, r.width, r.height, gpu_ms, r.zbuffer_ms, r.zbuffer_new_mesh_ms,
                r.zbuffer_graphics_only_ms, r.raycast_bvh_ms, r.raycast_ms, r.scanline_ms, r.scanline_1t_ms, embree,
                r.raycast_ms / zb, r.scanline_ms / zb, embree_ratio);
            j["projections"].push_back(
                {{"mesh", r.mesh},
                 {"faces", r.faces},
                 {"width", r.width},
                 {"height", r.height},
                 {"zbuffer_gpu_ms", gpu_times ? nlohmann::json(r.zbuffer_gpu_ms) : nlohmann::json()},
                 {"zbuffer_ms", r.zbuffer_ms},
                 {"zbuffer_new_mesh_ms", r.zbuffer_new_mesh_ms},
                 {"zbuffer_graphics_only_ms", r.zbuffer_graphics_only_ms},
                 {"raycast_bvh_ms", r.raycast_bvh_ms},
                 {"raycast_ms", r.raycast_ms},
                 {"scanline_ms", r.scanline_ms},
                 {"scanline_single_thread_ms", r.scanline_1t_ms},
                 {"embree_bvh_ms", r.embree_bvh_ms},
                 {"embree_ms", r.embree_ms},
                 {"raycast_over_zbuffer", r.raycast_ms / zb},
                 {"scanline_over_zbuffer", r.scanline_ms / zb},
                 {"embree_over_zbuffer", r.embree_ms > 0 ? r.embree_ms / zb : 0.0},
                 {"embree_new_mesh_over_zbuffer_new_mesh",
                  r.embree_ms > 0 ? (r.embree_bvh_ms + r.embree_ms) / r.zbuffer_new_mesh_ms : 0.0}});
        }
    }

    // Batch: many rotations of ~10K-face meshes at 144x144 in one graph execution.
    const auto batch = o.batch_meshes.empty() ? default_batch_meshes() : o.batch_meshes;
    if (!batch.empty() && o.batch_images > 0) {
        passes::CylinderZBuffer z(*ctx, 144, 144, o.zbuffer());
        // GPU time from a timestamped twin, as for single images.
        passes::CylinderZBuffer timed(*ctx, 144, 144, o.zbuffer(true));
        std::vector<passes::CylinderZBuffer::Job> jobs;
        std::vector<std::uint32_t> ids;
        for (const auto& path : batch) {
            const geo::Mesh mesh = geo::load_mesh(path);
            const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, passes::fit_cylinder_frame(mesh));
            ids.push_back(z.add_mesh(cyl));
            timed.add_mesh(cyl);
        }
        for (std::uint32_t k = 0; k < o.batch_images; ++k)
            jobs.push_back({ids[k % ids.size()], rotation(360.0 * k / o.batch_images, 10.0 * (k % 7))});
        z.project(jobs);  // warm-up
        std::vector<double> wall, gpu;
        for (int k = 0; k < runs; ++k) {
            wall.push_back(time_ms([&] { z.project(jobs); }));
            timed.project(jobs);
            gpu.push_back(timed.last_gpu_ms());
        }
        const double per_second = 1000.0 * o.batch_images / median(wall);
        char gpu_ms[32] = "";
        if (gpu_times) std::snprintf(gpu_ms, sizeof gpu_ms, " (%.1f ms GPU)", median(gpu));
        std::printf(
            "batch: %u images of 144x144 from %zu meshes of ~10K faces per execution: %.1f ms wall%s, "
            "%.0f images/s\n",
            o.batch_images, batch.size(), median(wall), gpu_ms, per_second);
        j["batch"] = {{"images", o.batch_images},
                      {"width", 144},
                      {"height", 144},
                      {"meshes", batch},
                      {"wall_ms", median(wall)},
                      {"gpu_ms", gpu_times ? nlohmann::json(median(gpu)) : nlohmann::json()},
                      {"images_per_second", per_second}};
    }
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

struct ReconstructBenchOptions {
    std::vector<std::string> meshes;
    std::string size = "1024x512";
    std::uint32_t runs = 5;
    std::string json;
};

// Reconstruction of a cylindrical image (made by the scanline method) on the GPU and by the CPU
// reference, medians of N runs.
void run_reconstruct_bench(const ReconstructBenchOptions& o, const GlobalOptions& global) {
    auto ctx = open_context(global);
    const auto size = parse_size(o.size);
    const int runs = int(o.runs);
    nlohmann::json j;
    std::printf("gimg bench reconstruct on %s; %ux%u images; medians of %d runs; times in ms\n",
                ctx->device_info().summary().c_str(), size[0], size[1], runs);
    std::printf("%-22s %9s %9s %9s %9s %7s\n", "mesh", "vertices", "GPU", "GPU wall", "CPU ref", "cpu/gpu");
    std::vector<std::string> meshes = o.meshes;
    if (meshes.empty()) meshes = {(shared_mesh_dir() / "armadillo.off").string()};
    for (const std::string& path : meshes) {
        const geo::Mesh mesh = geo::load_mesh(path);
        const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
        const auto image = passes::cylinder_scanline(passes::make_cylinder_mesh(mesh, frame), size[0], size[1]);
        passes::reconstruct_gpu(*ctx, image, frame);  // pipelines compile once
        std::vector<double> gpu, wall, cpu;
        std::size_t vertices = 0;
        for (int k = 0; k < runs; ++k) {
            passes::ReconstructStats stats;
            wall.push_back(
                time_ms([&] { vertices = passes::reconstruct_gpu(*ctx, image, frame, {}, &stats).vertex_count(); }));
            gpu.push_back(stats.gpu_ms);
            cpu.push_back(time_ms([&] { passes::reconstruct_cpu(image, frame); }));
        }
        const std::string name = std::filesystem::path(path).filename().string();
        std::printf("%-22s %9zu %9.2f %9.2f %9.2f %7.2f\n", name.c_str(), vertices, median(gpu), median(wall),
                    median(cpu), median(cpu) / median(wall));
        j["reconstructions"].push_back({{"mesh", name},
                                        {"width", size[0]},
                                        {"height", size[1]},
                                        {"vertices", vertices},
                                        {"gpu_ms", median(gpu)},
                                        {"gpu_wall_ms", median(wall)},
                                        {"cpu_ms", median(cpu)}});
    }
    add_machine_figures(j, ctx.get());
    write_json(o.json, j);
}

}  // namespace

void add_bench_command(CLI::App& app, const GlobalOptions& global) {
    auto* bench = app.add_subcommand("bench", "Benchmarks");
    bench->require_subcommand(1);
    auto opts = std::make_shared<BenchOptions>();
    auto* cyl = bench->add_subcommand("cylinder", "zbuffer vs raycast vs scanline (vs Embree) per projection");
    cyl->add_option("--mesh", opts->meshes, "Meshes (default: armadillo, bunny, derived/bunny_loop1, dragon)");
    cyl->add_option("--size", opts->sizes, "Sizes: WxH or auto (default: auto and 540x270)");
    add_count_option(cyl, "--runs", opts->runs, 1, 1000, "Runs per case; the median is reported (default 5)");
    add_count_option(cyl, "--batch-images", opts->batch_images, 0, 4096,
                     "Images per batch execution at 144x144 (0: skip)");
    cyl->add_option("--batch-mesh", opts->batch_meshes, "Meshes for the batch case (default: ~10K-face shared meshes)");
    add_count_option(cyl, "--small-pixels", opts->small_pixels, 0, UINT32_MAX,
                     "zbuffer: pieces of at most this many pixels are decided in the classify pass (0: none; "
                     "default 64)");
    cyl->add_option("--large-pieces", opts->large_pieces,
                    "zbuffer: larger pieces through the graphics pipeline or a compute pass (default auto: compute on "
                    "CPU devices, graphics on GPUs)")
        ->check(CLI::IsMember({"auto", "graphics", "compute"}));
    cyl->add_option("--json", opts->json, "Write the figures as JSON");
    cyl->callback([opts, &global] { run_writing({}, {json_output(opts->json)}, [&] { run_bench(*opts, global); }); });
    auto ropts = std::make_shared<ReconstructBenchOptions>();
    auto* rec = bench->add_subcommand("reconstruct", "Reconstruction on the GPU vs the CPU reference");
    rec->add_option("--mesh", ropts->meshes, "Meshes to project and reconstruct (default: armadillo)");
    rec->add_option("--size", ropts->size, "Image size WxH (default 1024x512)");
    add_count_option(rec, "--runs", ropts->runs, 1, 1000, "Runs; the median is reported (default 5)");
    rec->add_option("--json", ropts->json, "Write the figures as JSON");
    rec->callback([ropts, &global] {
        run_writing({}, {json_output(ropts->json)}, [&] { run_reconstruct_bench(*ropts, global); });
    });
    add_bench_sphere_command(*bench, global);
    add_bench_hierarchy_command(*bench, global);
    add_bench_gim_command(*bench, global);
    add_bench_quadmap_command(*bench, global);
    add_bench_maps_command(*bench, global);
    add_bench_retrieval_command(*bench, global);
    add_bench_engine_command(*bench, global);
}

}  // namespace gimg::cli

// Grid reconstruction as compute passes: level-of-detail reductions, points, the occlusion test per
// block, prefix sums (passes/primitives) for compaction, then vertices and triangles written in
// place. Mirrors reconstruct_cpu.cpp decision for decision (reconstruct_rules.h).
#include "gimg/passes/reconstruct.h"

#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/error.h"
#include "gimg/passes/primitives.h"

#include "reconstruct/blocks_comp.h"
#include "reconstruct/cylinder_points_comp.h"
#include "reconstruct/emit_triangles_comp.h"
#include "reconstruct/emit_vertices_comp.h"
#include "reconstruct/position_points_comp.h"
#include "reconstruct/reduce_comp.h"
#include "reconstruct_rules.h"

#include <cmath>
#include <cstring>

namespace gimg::passes {

namespace {

const Spirv kCylinderPoints = GIMG_SPIRV(gimg_spv_reconstruct_cylinder_points_comp);
const Spirv kPositionPoints = GIMG_SPIRV(gimg_spv_reconstruct_position_points_comp);
const Spirv kBlocks = GIMG_SPIRV(gimg_spv_reconstruct_blocks_comp);
const Spirv kEmitVertices = GIMG_SPIRV(gimg_spv_reconstruct_emit_vertices_comp);
const Spirv kEmitTriangles = GIMG_SPIRV(gimg_spv_reconstruct_emit_triangles_comp);
const Spirv kReduce = GIMG_SPIRV(gimg_spv_reconstruct_reduce_comp);

struct Size2 {
    std::uint32_t width, height;
};
struct BlocksPush {
    std::uint32_t width, height, wrap, cylindrical;
    float threshold;
};
struct EmitPush {
    std::uint32_t width, height, wrap, cylindrical;
};
struct ReducePush {
    std::uint32_t width, height, channels;
};

Buffer upload(Context& ctx, const void* data, std::size_t bytes, const char* name) {
    Buffer b = ctx.create_buffer({bytes, name});
    ctx.upload(b, data, bytes);
    return b;
}

// One input image, as floats with NaN for empty pixels (1 channel: d, 3: xyz).
struct GridInput {
    std::vector<float> values;
    std::uint32_t channels, width, height;
    bool cylindrical;
    float threshold;  // applied after the reductions
};

geo::Mesh run(Context& ctx, const GridInput& in, std::uint32_t lod, const CylinderFrame* frame, ReconstructStats* stats) {
    if (!ctx.device_info().shader_float64)
        throw Error(ErrorKind::Unsupported, "GPU reconstruction needs shaderFloat64 (use the CPU path)");
    const std::uint32_t W = in.width >> lod, H = in.height >> lod;
    const std::uint64_t pixels = std::uint64_t(W) * H, blocks = std::uint64_t(in.cylindrical ? W : W - 1) * (H - 1);
    if (6 * 4 * blocks > ctx.device_info().max_storage_buffer_range)
        throw geo::InputError("a " + std::to_string(W) + "x" + std::to_string(H) +
                              " image is too large to reconstruct on this device at once (use --lod)");

    Buffer source = upload(ctx, in.values.data(), in.values.size() * 4, "geometry image");
    Buffer directions, frame_buf;
    if (in.cylindrical) {
        const auto dirs = cylinder_directions(W);
        directions = upload(ctx, dirs.data(), dirs.size() * 16, "directions");
        double f[16] = {};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) f[3 * r + c] = frame->rotation[c][r];
        for (int k = 0; k < 3; ++k) f[9 + k] = frame->translation[k];
        f[12] = frame->scale;
        frame_buf = upload(ctx, f, sizeof f, "frame");
    }
    Buffer out_vertices = ctx.create_buffer({std::max<std::uint64_t>(pixels, 1) * 12, "vertices"});
    Buffer out_triangles = ctx.create_buffer({std::max<std::uint64_t>(2 * blocks, 1) * 12, "triangles"});
    Buffer vertex_index_buf = ctx.create_buffer({pixels * 4, "vertex index"});
    Buffer triangle_end_buf = ctx.create_buffer({std::max<std::uint64_t>(blocks, 1) * 4, "triangle ends"});

    Graph g(ctx);
    auto image = g.import_buffer(source);
    // Level-of-detail reductions, each halving both sides.
    std::uint32_t w = in.width, h = in.height;
    for (std::uint32_t k = 0; k < lod; ++k) {
        w /= 2, h /= 2;
        auto reduced = g.create_buffer({std::uint64_t(w) * h * in.channels * 4, "reduced image"});
        const ReducePush push{w, h, in.channels};
        g.add_compute_pass("reduce " + std::to_string(k + 1), [&](PassBuilder& b) {
            b.read(image, Access::ComputeRead);
            reduced = b.write(reduced, Access::ComputeWrite);
        }, [=, src = image, dst = reduced](Cmd& c) { c.dispatch_threads(kReduce, {w, h}, {src, dst}, push); });
        image = reduced;
    }
    auto points = g.create_buffer({pixels * 16, "points"});
    auto valid = g.create_buffer({pixels * 4, "valid"});
    const Size2 size{W, H};
    if (in.cylindrical) {
        auto dirs = g.import_buffer(directions), fr = g.import_buffer(frame_buf);
        g.add_compute_pass("points", [&](PassBuilder& b) {
            b.read(image, Access::ComputeRead);
            b.read(dirs, Access::ComputeRead);
            b.read(fr, Access::ComputeRead);
            points = b.write(points, Access::ComputeWrite);
            valid = b.write(valid, Access::ComputeWrite);
        }, [=](Cmd& c) { c.dispatch_threads(kCylinderPoints, {W, H}, {image, dirs, fr, points, valid}, size); });
    } else {
        g.add_compute_pass("points", [&](PassBuilder& b) {
            b.read(image, Access::ComputeRead);
            points = b.write(points, Access::ComputeWrite);
            valid = b.write(valid, Access::ComputeWrite);
        }, [=](Cmd& c) { c.dispatch_threads(kPositionPoints, {W, H}, {image, points, valid}, size); });
    }
    auto counts = g.create_buffer({std::max<std::uint64_t>(blocks, 1) * 4, "block triangle counts"});
    const std::uint32_t blocks_per_row = in.cylindrical ? W : W - 1;
    const BlocksPush blocks_push{W, H, in.cylindrical ? 1u : 0u, in.cylindrical ? 1u : 0u, in.threshold};
    g.add_compute_pass("occlusion test", [&](PassBuilder& b) {
        b.read(points, Access::ComputeRead);
        b.read(image, Access::ComputeRead);
        counts = b.write(counts, Access::ComputeWrite);
    }, [=](Cmd& c) { c.dispatch_threads(kBlocks, {blocks_per_row, H - 1}, {points, image, counts}, blocks_push); });
    auto vertex_index = add_inclusive_scan(g, valid, g.import_buffer(vertex_index_buf), std::uint32_t(pixels), "vertex scan");
    auto triangle_end =
        add_inclusive_scan(g, counts, g.import_buffer(triangle_end_buf), std::uint32_t(blocks), "triangle scan");
    auto verts = g.import_buffer(out_vertices);
    const std::uint32_t count = std::uint32_t(pixels);
    g.add_compute_pass("emit vertices", [&](PassBuilder& b) {
        b.read(points, Access::ComputeRead);
        b.read(vertex_index, Access::ComputeRead);
        verts = b.write(verts, Access::ComputeWrite);
    }, [=](Cmd& c) { c.dispatch_threads(kEmitVertices, {count}, {points, vertex_index, verts}, count); });
    auto tris = g.import_buffer(out_triangles);
    const EmitPush emit_push{W, H, in.cylindrical ? 1u : 0u, in.cylindrical ? 1u : 0u};
    g.add_compute_pass("emit triangles", [&](PassBuilder& b) {
        b.read(points, Access::ComputeRead);
        b.read(image, Access::ComputeRead);
        b.read(counts, Access::ComputeRead);
        b.read(triangle_end, Access::ComputeRead);
        b.read(vertex_index, Access::ComputeRead);
        tris = b.write(tris, Access::ComputeWrite);
    }, [=](Cmd& c) {
        c.dispatch_threads(kEmitTriangles, {blocks_per_row, H - 1}, {points, image, counts, triangle_end, vertex_index, tris},
                           emit_push);
    });
    g.export_buffer(vertex_index, Access::TransferSrc);
    g.export_buffer(triangle_end, Access::TransferSrc);
    g.export_buffer(verts, Access::TransferSrc);
    g.export_buffer(tris, Access::TransferSrc);
    Plan plan = g.compile();
    const bool timed = ctx.device_info().timestamp_period_ns > 0.0;
    plan.execute({.wait = true, .timestamps = timed});

    std::uint32_t vertex_count = 0, triangle_count = 0;
    ctx.download(vertex_index_buf, &vertex_count, 4, (pixels - 1) * 4);
    if (blocks > 0) ctx.download(triangle_end_buf, &triangle_count, 4, (blocks - 1) * 4);
    std::vector<float> positions(3 * std::size_t(vertex_count));
    std::vector<std::uint32_t> indices(3 * std::size_t(triangle_count));
    if (vertex_count) ctx.download(out_vertices, positions.data(), positions.size() * 4);
    if (triangle_count) ctx.download(out_triangles, indices.data(), indices.size() * 4);

    geo::Mesh mesh;
    mesh.positions.resize(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i)
        mesh.positions[i] = glm::dvec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
    mesh.triangles.resize(triangle_count);
    std::memcpy(mesh.triangles.data(), indices.data(), indices.size() * 4);
    if (stats) {
        stats->width = W;
        stats->height = H;
        stats->threshold = in.threshold;
        stats->gpu_ms = timed ? plan.total_gpu_ms() : 0.0;
    }
    return mesh;
}

}  // namespace

geo::Mesh reconstruct_gpu(Context& ctx, const CylinderImage& image, const CylinderFrame& frame,
                          const ReconstructOptions& options, ReconstructStats* stats) {
    detail::check_reconstructible(image.width, image.height, options.lod);
    GridInput in{std::vector<float>(image.distance.size()), 1, image.width, image.height, true, 0.0f};
    for (std::size_t i = 0; i < in.values.size(); ++i)
        in.values[i] = image.covered[i] ? image.distance[i] : std::numeric_limits<float>::quiet_NaN();
    // The default threshold comes from the image the triangles are made from.
    in.threshold = options.threshold ? *options.threshold
                                     : default_cylinder_threshold(options.lod ? lod_reduce(image, options.lod) : image);
    geo::Mesh mesh = run(ctx, in, options.lod, &frame, stats);
    const CylinderImage reduced = options.lod ? lod_reduce(image, options.lod) : image;
    if (stats) stats->holes = detail::full_blocks(reduced.covered, reduced.width, reduced.height, true) - mesh.face_count() / 2;
    if (options.fill_caps) detail::add_caps(mesh, reduced, frame);
    detail::finish_mesh(mesh);
    return mesh;
}

geo::Mesh reconstruct_gpu(Context& ctx, const PositionImage& image, const ReconstructOptions& options,
                          ReconstructStats* stats) {
    detail::check_reconstructible(image.width, image.height, options.lod);
    if (options.fill_caps) throw geo::InputError("--fill-caps is for cylindrical images");
    GridInput in{image.xyz, 3, image.width, image.height, false,
                 options.threshold ? *options.threshold : std::numeric_limits<float>::infinity()};
    for (std::size_t i = 0; i < image.covered.size(); ++i)
        if (!image.covered[i]) in.values[3 * i] = std::numeric_limits<float>::quiet_NaN();
    geo::Mesh mesh = run(ctx, in, options.lod, nullptr, stats);
    if (stats) {
        const PositionImage reduced = options.lod ? lod_reduce(image, options.lod) : image;
        stats->holes = detail::full_blocks(reduced.covered, reduced.width, reduced.height, false) - mesh.face_count() / 2;
    }
    detail::finish_mesh(mesh);
    return mesh;
}

}  // namespace gimg::passes

// Grid reconstruction as compute passes: level-of-detail reductions, points, the occlusion test per
// block, prefix sums (passes/primitives) for compaction, then vertices and triangles written in
// place. Mirrors reconstruct_cpu.cpp decision for decision (reconstruct_rules.h).
#include "gimg/passes/reconstruct.h"

#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"
#include "gimg/engine/plan.h"
#include "gimg/geometry/error.h"
#include "gimg/passes/primitives.h"

#include "reconstruct/blocks_comp.h"
#include "reconstruct/cylinder_points_comp.h"
#include "reconstruct/emit_triangles_comp.h"
#include "reconstruct/emit_vertices_comp.h"
#include "reconstruct/position_points_comp.h"
#include "reconstruct/reduce_comp.h"
#include "reconstruct_rules.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

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

// The grid an image is reconstructed from: 1 channel (d) for cylindrical images, 3 (xyz) for
// position images, NaN in the first channel where empty.
struct Grid {
    std::uint32_t channels, width, height;
    bool cylindrical;
};

// Small host data into a transient buffer at every execution, in vkCmdUpdateBuffer's 64 KiB pieces.
void update_in_pieces(Cmd& c, BufferHandle buffer, const std::vector<std::uint8_t>& bytes) {
    constexpr std::size_t kPiece = 65536;
    for (std::size_t at = 0; at < bytes.size(); at += kPiece)
        c.update(buffer, bytes.data() + at, std::min(kPiece, bytes.size() - at), at);
}

ReconstructHandles record_grid(Graph& g, BufferHandle image, const Grid& in, std::uint32_t lod, float threshold,
                               const CylinderFrame* frame, const std::string& name) {
    const DeviceInfo* info = g.device_info();
    if (info && !info->shader_float64)
        throw Error(ErrorKind::Unsupported, "GPU reconstruction needs shaderFloat64 (use the CPU path)");
    detail::check_reconstructible(in.width, in.height, lod);
    const std::uint32_t W = in.width >> lod, H = in.height >> lod;
    const std::uint64_t pixels = std::uint64_t(W) * H, blocks = std::uint64_t(in.cylindrical ? W : W - 1) * (H - 1);
    if (info && 6 * 4 * blocks > info->max_storage_buffer_range)
        throw geo::InputError("a " + std::to_string(W) + "x" + std::to_string(H) +
                              " image is too large to reconstruct on this device at once (use --lod)");
    // Level-of-detail reductions, each halving both sides.
    std::uint32_t w = in.width, h = in.height;
    for (std::uint32_t k = 0; k < lod; ++k) {
        w /= 2, h /= 2;
        auto reduced = g.create_buffer({std::uint64_t(w) * h * in.channels * 4, name + " reduced image"});
        const ReducePush push{w, h, in.channels};
        g.add_compute_pass(
            name + ": reduce " + std::to_string(k + 1),
            [&](PassBuilder& b) {
                b.read(image, Access::ComputeRead);
                reduced = b.write(reduced, Access::ComputeWrite);
            },
            [=, src = image, dst = reduced](Cmd& c) {
                c.dispatch_threads(kReduce, {w, h}, {src, dst}, push);
            });
        image = reduced;
    }
    auto points = g.create_buffer({pixels * 16, name + " points"});
    auto valid = g.create_buffer({pixels * 4, name + " valid"});
    const Size2 size{W, H};
    if (in.cylindrical) {
        // The directions table and the frame (R row by row, t, s) in double, as the CPU path uses them.
        const auto dirs = cylinder_directions(W);
        auto dir_bytes = std::make_shared<std::vector<std::uint8_t>>(dirs.size() * 16);
        std::memcpy(dir_bytes->data(), dirs.data(), dir_bytes->size());
        auto frame_bytes = std::make_shared<std::vector<std::uint8_t>>(16 * sizeof(double));
        double f[16] = {};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) f[3 * r + c] = frame->rotation[c][r];
        for (int k = 0; k < 3; ++k) f[9 + k] = frame->translation[k];
        f[12] = frame->scale;
        std::memcpy(frame_bytes->data(), f, sizeof f);
        auto dir_buf = g.create_buffer({dir_bytes->size(), name + " directions"});
        auto frame_buf = g.create_buffer({frame_bytes->size(), name + " frame"});
        g.add_compute_pass(
            name + ": frame",
            [&](PassBuilder& b) {
                dir_buf = b.write(dir_buf, Access::TransferDst);
                frame_buf = b.write(frame_buf, Access::TransferDst);
            },
            [=](Cmd& c) {
                update_in_pieces(c, dir_buf, *dir_bytes);
                update_in_pieces(c, frame_buf, *frame_bytes);
            });
        g.add_compute_pass(
            name + ": points",
            [&](PassBuilder& b) {
                b.read(image, Access::ComputeRead);
                b.read(dir_buf, Access::ComputeRead);
                b.read(frame_buf, Access::ComputeRead);
                points = b.write(points, Access::ComputeWrite);
                valid = b.write(valid, Access::ComputeWrite);
            },
            [=](Cmd& c) {
                c.dispatch_threads(kCylinderPoints, {W, H}, {image, dir_buf, frame_buf, points, valid}, size);
            });
    } else {
        g.add_compute_pass(
            name + ": points",
            [&](PassBuilder& b) {
                b.read(image, Access::ComputeRead);
                points = b.write(points, Access::ComputeWrite);
                valid = b.write(valid, Access::ComputeWrite);
            },
            [=](Cmd& c) {
                c.dispatch_threads(kPositionPoints, {W, H}, {image, points, valid}, size);
            });
    }
    auto counts = g.create_buffer({std::max<std::uint64_t>(blocks, 1) * 4, name + " block triangle counts"});
    const std::uint32_t blocks_per_row = in.cylindrical ? W : W - 1;
    const BlocksPush blocks_push{W, H, in.cylindrical ? 1u : 0u, in.cylindrical ? 1u : 0u, threshold};
    g.add_compute_pass(
        name + ": occlusion test",
        [&](PassBuilder& b) {
            b.read(points, Access::ComputeRead);
            b.read(image, Access::ComputeRead);
            counts = b.write(counts, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kBlocks, {blocks_per_row, H - 1}, {points, image, counts}, blocks_push);
        });
    auto vertex_index = add_inclusive_scan(g, valid, g.create_buffer({pixels * 4, name + " vertex index"}),
                                           std::uint32_t(pixels), name + ": vertex scan");
    auto triangle_end = add_inclusive_scan(
        g, counts, g.create_buffer({std::max<std::uint64_t>(blocks, 1) * 4, name + " triangle ends"}),
        std::uint32_t(blocks), name + ": triangle scan");
    auto verts = g.create_buffer({std::max<std::uint64_t>(pixels, 1) * 12, name + " vertices"});
    const std::uint32_t count = std::uint32_t(pixels);
    g.add_compute_pass(
        name + ": emit vertices",
        [&](PassBuilder& b) {
            b.read(points, Access::ComputeRead);
            b.read(vertex_index, Access::ComputeRead);
            verts = b.write(verts, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kEmitVertices, {count}, {points, vertex_index, verts}, count);
        });
    auto tris = g.create_buffer({std::max<std::uint64_t>(2 * blocks, 1) * 12, name + " triangles"});
    const EmitPush emit_push{W, H, in.cylindrical ? 1u : 0u, in.cylindrical ? 1u : 0u};
    g.add_compute_pass(
        name + ": emit triangles",
        [&](PassBuilder& b) {
            b.read(points, Access::ComputeRead);
            b.read(image, Access::ComputeRead);
            b.read(counts, Access::ComputeRead);
            b.read(triangle_end, Access::ComputeRead);
            b.read(vertex_index, Access::ComputeRead);
            tris = b.write(tris, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kEmitTriangles, {blocks_per_row, H - 1},
                               {points, image, counts, triangle_end, vertex_index, tris}, emit_push);
        });
    return {verts, tris, vertex_index, triangle_end, W, H, pixels, blocks, threshold};
}

// The grid triangles a plan left at the handles, without normals.
geo::Mesh download_grid(Context& ctx, Plan& plan, const ReconstructHandles& h) {
    std::uint32_t vertex_count = 0, triangle_count = 0;
    ctx.download(plan.buffer(h.vertex_index), &vertex_count, 4, (h.pixels - 1) * 4);
    if (h.blocks > 0) ctx.download(plan.buffer(h.triangle_end), &triangle_count, 4, (h.blocks - 1) * 4);
    std::vector<float> positions(3 * std::size_t(vertex_count));
    std::vector<std::uint32_t> indices(3 * std::size_t(triangle_count));
    if (vertex_count) ctx.download(plan.buffer(h.vertices), positions.data(), positions.size() * 4);
    if (triangle_count) ctx.download(plan.buffer(h.triangles), indices.data(), indices.size() * 4);
    geo::Mesh mesh;
    mesh.positions.resize(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i)
        mesh.positions[i] = glm::dvec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
    mesh.triangles.resize(triangle_count);
    std::memcpy(mesh.triangles.data(), indices.data(), indices.size() * 4);
    return mesh;
}

// Runs a one-image graph: the image uploaded, reconstructed, read back.
geo::Mesh run(Context& ctx, const std::vector<float>& values, const Grid& in, std::uint32_t lod, float threshold,
              const CylinderFrame* frame, ReconstructStats* stats) {
    Buffer source = ctx.create_buffer({values.size() * 4, "geometry image"});
    ctx.upload(source, values.data(), values.size() * 4);
    Graph g(ctx);
    const ReconstructHandles h = record_grid(g, g.import_buffer(source), in, lod, threshold, frame, "reconstruct");
    export_reconstruction(g, h);
    Plan plan = g.compile();
    const bool timed = ctx.device_info().timestamp_period_ns > 0.0;
    plan.execute({.wait = true, .timestamps = timed});
    geo::Mesh mesh = download_grid(ctx, plan, h);
    if (stats) {
        stats->width = h.width;
        stats->height = h.height;
        stats->threshold = threshold;
        stats->gpu_ms = timed ? plan.total_gpu_ms() : 0.0;
    }
    return mesh;
}

}  // namespace

ReconstructHandles add_reconstruct(Graph& graph, const CylinderImagesHandle& images, std::uint32_t index,
                                   const CylinderFrame& frame, float threshold, std::uint32_t lod,
                                   const std::string& name) {
    if (index >= images.count)
        throw geo::InputError("add_reconstruct: image " + std::to_string(index) + " of " +
                              std::to_string(images.count));
    BufferHandle image = images.distance;
    if (images.count > 1) {  // its own buffer, so the passes read it from offset 0
        const VkDeviceSize bytes = VkDeviceSize(images.width) * images.height * 4;
        auto one = graph.create_buffer({bytes, name + " image"});
        graph.add_compute_pass(
            name + ": pick image",
            [&](PassBuilder& b) {
                b.read(image, Access::TransferSrc);
                one = b.write(one, Access::TransferDst);
            },
            [=](Cmd& c) { c.copy(image, one, bytes, bytes * index, 0); });
        image = one;
    }
    return record_grid(graph, image, {1, images.width, images.height, true}, lod, threshold, &frame, name);
}

ReconstructHandles add_reconstruct(Graph& graph, BufferHandle xyz, std::uint32_t width, std::uint32_t height,
                                   float threshold, std::uint32_t lod, const std::string& name) {
    return record_grid(graph, xyz, {3, width, height, false}, lod, threshold, nullptr, name);
}

void export_reconstruction(Graph& graph, const ReconstructHandles& handles) {
    graph.export_buffer(handles.vertices, Access::TransferSrc);
    graph.export_buffer(handles.triangles, Access::TransferSrc);
    graph.export_buffer(handles.vertex_index, Access::TransferSrc);
    graph.export_buffer(handles.triangle_end, Access::TransferSrc);
}

geo::Mesh read_reconstruction(Context& ctx, Plan& plan, const ReconstructHandles& handles) {
    geo::Mesh mesh = download_grid(ctx, plan, handles);
    detail::finish_mesh(mesh);
    return mesh;
}

geo::Mesh reconstruct_gpu(Context& ctx, const CylinderImage& image, const CylinderFrame& frame,
                          const ReconstructOptions& options, ReconstructStats* stats) {
    detail::check_reconstructible(image.width, image.height, options.lod);
    std::vector<float> values(image.distance.size());
    for (std::size_t i = 0; i < values.size(); ++i)
        values[i] = image.covered[i] ? image.distance[i] : std::numeric_limits<float>::quiet_NaN();
    // The default threshold comes from the image the triangles are made from.
    const float threshold = options.threshold
                                ? *options.threshold
                                : default_cylinder_threshold(options.lod ? lod_reduce(image, options.lod) : image);
    geo::Mesh mesh = run(ctx, values, {1, image.width, image.height, true}, options.lod, threshold, &frame, stats);
    const CylinderImage reduced = options.lod ? lod_reduce(image, options.lod) : image;
    if (stats)
        stats->holes =
            detail::full_blocks(reduced.covered, reduced.width, reduced.height, true) - mesh.face_count() / 2;
    if (options.fill_caps) detail::add_caps(mesh, reduced, frame);
    detail::finish_mesh(mesh);
    return mesh;
}

geo::Mesh reconstruct_gpu(Context& ctx, const PositionImage& image, const ReconstructOptions& options,
                          ReconstructStats* stats) {
    detail::check_reconstructible(image.width, image.height, options.lod);
    if (options.fill_caps) throw geo::InputError("--fill-caps is for cylindrical images");
    std::vector<float> values = image.xyz;
    for (std::size_t i = 0; i < image.covered.size(); ++i)
        if (!image.covered[i]) values[3 * i] = std::numeric_limits<float>::quiet_NaN();
    const float threshold = options.threshold ? *options.threshold : std::numeric_limits<float>::infinity();
    geo::Mesh mesh = run(ctx, values, {3, image.width, image.height, false}, options.lod, threshold, nullptr, stats);
    if (stats) {
        const PositionImage reduced = options.lod ? lod_reduce(image, options.lod) : image;
        stats->holes =
            detail::full_blocks(reduced.covered, reduced.width, reduced.height, false) - mesh.face_count() / 2;
    }
    detail::finish_mesh(mesh);
    return mesh;
}

}  // namespace gimg::passes

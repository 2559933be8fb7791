// The GPU cylindrical Z-buffer: classify + split + small pieces (compute), large pieces (the
// graphics pipeline's curved raster, or a compute pass on CPU devices), one graph.
#include "gimg/passes/cylinder.h"
#include "gimg/geometry/error.h"

#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/vertex_order.h"

#include "gimg/engine/texel_array.h"

#include "cylinder/classify_comp.h"
#include "cylinder/classify_float_comp.h"
#include "cylinder/cylinder_layout.h"
#include "cylinder/large_pieces_comp.h"
#include "cylinder/large_pieces_float_comp.h"
#include "cylinder/zbuffer_float_frag.h"
#include "cylinder/zbuffer_frag.h"
#include "cylinder/zbuffer_vert.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>

namespace gimg::passes {

namespace {

const Spirv kClassify = GIMG_SPIRV(gimg_spv_cylinder_classify_comp);
const Spirv kClassifyFloat = GIMG_SPIRV(gimg_spv_cylinder_classify_float_comp);
const Spirv kLargePieces = GIMG_SPIRV(gimg_spv_cylinder_large_pieces_comp);
const Spirv kLargePiecesFloat = GIMG_SPIRV(gimg_spv_cylinder_large_pieces_float_comp);
const RasterState kDepthMax{.cull = CullMode::None, .depth_test = true, .depth_write = true,
                            .depth_compare = CompareOp::Less};
const RasterProgram kZBuffer{GIMG_SPIRV(gimg_spv_cylinder_zbuffer_vert), GIMG_SPIRV(gimg_spv_cylinder_zbuffer_frag),
                             kDepthMax};
const RasterProgram kZBufferFloat{GIMG_SPIRV(gimg_spv_cylinder_zbuffer_vert),
                                  GIMG_SPIRV(gimg_spv_cylinder_zbuffer_float_frag), kDepthMax};

// Mirrors struct CylinderJob in shaders/cylinder/cylinder_job.h (std430).
struct JobGpu {
    float rows[12];
    std::uint32_t first_face, face_count, face_prefix, vertex_offset, tile_x, tile_y, pad0, pad1;
};
static_assert(sizeof(JobGpu) == 80);
constexpr std::uint32_t kTexelsPerJob = sizeof(JobGpu) / 16;  // classify_body.glsl's load_job

// Mirrors the Args block of shaders/cylinder/piece_passes.glsl.
struct PieceArgs {
    std::uint32_t vertex_count, instance_count, first_vertex, first_instance;  // VkDrawIndirectCommand
    std::uint32_t groups_x, groups_y, groups_z;                                // VkDispatchIndirectCommand
    std::uint32_t rect_count;
};
static_assert(sizeof(PieceArgs) == 32);
constexpr VkDeviceSize kDispatchArgsOffset = offsetof(PieceArgs, groups_x);

struct ClassifyPush {
    std::uint32_t total_faces, job_count, width, height, max_rects, small_pixels, atlas_width;
};
struct DrawPush {
    float atlas_size[2];
    std::uint32_t image_size[2];
};

// The distance an ordered key of the classify pass stands for (shaders/cylinder/distance_key.glsl).
float key_distance(std::uint32_t key) {
    return std::bit_cast<float>((key & 0x80000000u) != 0 ? key & 0x7fffffffu : ~key);
}

// The faces' Morton curve runs through 128^3 cells: two radix passes instead of six (add_mesh of
// dragon's 871K faces 46-50 -> 33-36 ms), and a cell still holds only a few pixels' worth of faces.
constexpr int kFaceOrderBitsPerAxis = 7;

struct MeshRange {
    std::uint32_t vertex_offset, first_face, face_count;
};

}  // namespace

std::vector<std::array<double, 2>> cylinder_directions(std::uint32_t width) {
    std::vector<std::array<double, 2>> d(width);
    for (std::uint32_t u = 0; u < width; ++u) {
        const double theta = 2.0 * std::numbers::pi * (double(u) + 0.5) / double(width);
        d[u] = {std::cos(theta), std::sin(theta)};
    }
    return d;
}

struct CylinderZBuffer::State {
    Context& ctx;
    std::uint32_t width, height, small_pixels;
    bool use_double, timestamps;
    bool graphics;  // large pieces through the graphics pipeline (else large_pieces.comp)

    std::vector<float> positions;
    std::vector<std::uint32_t> triangles;
    std::vector<MeshRange> meshes;
    bool geometry_dirty = true;

    // The batch's jobs: written by the host into jobs_upload, copied by the plan into jobs_buf (for
    // the graphics pipeline) and jobs_img (five texels a job, for the compute passes).
    Buffer jobs_upload, jobs_buf, rects_buf, args_buf;
    Image jobs_img;
    // Per atlas pixel, the largest t the compute passes found, as an ordered key (distance_key.glsl).
    Buffer keys_buf;
    // Where the plan copies the atlas, the keys and the arguments for the host, which merges atlas
    // and keys as it unpacks the images (on lavapipe a merge pass of its own cost about 0.35 ms an
    // image).
    Buffer atlas_readback, keys_readback, args_readback;
    // One texel a vertex, face and image column (texel_array.h: lavapipe gathers from images).
    Image positions_img, triangles_img, directions_img;
    Image atlas;  // the graphics pipeline's t per pixel (only with `graphics`)
    std::uint32_t job_capacity = 0, rect_capacity = 0, tiles_per_row = 1, atlas_width = 0, atlas_height = 0;
    std::optional<Plan> plan;

    // Read by the record callbacks at every execution.
    ClassifyPush classify{};
    DrawPush draw{};

    State(Context& c, std::uint32_t w, std::uint32_t h, const CylinderZBufferOptions& options)
        : ctx(c), width(w), height(h), small_pixels(options.small_pixels) {
        use_double = options.double_precision && ctx.device_info().shader_float64;
        timestamps = options.timestamps && ctx.device_info().timestamp_period_ns > 0.0;
        graphics = options.large_pieces == CylinderLargePieces::Graphics ||
                   (options.large_pieces == CylinderLargePieces::Auto &&
                    ctx.device_info().type != VK_PHYSICAL_DEVICE_TYPE_CPU);
        // Texel u: cos and sin of theta_u, as two doubles or two floats (the shaders' REAL2_OF_TEXEL).
        std::vector<glm::uvec4> texels(w, glm::uvec4(0));
        const auto dirs = cylinder_directions(w);
        for (std::uint32_t u = 0; u < w; ++u) {
            if (use_double) {
                std::memcpy(&texels[u], dirs[u].data(), 16);
            } else {
                const float f[2] = {float(dirs[u][0]), float(dirs[u][1])};
                std::memcpy(&texels[u], f, 8);
            }
        }
        directions_img = upload_texel_array(ctx, std::move(texels), Format::RGBA32U, "cylinder directions");
        args_buf = ctx.create_buffer({sizeof(PieceArgs), "cylinder large-piece arguments"});
        args_readback = ctx.create_buffer({sizeof(PieceArgs), "cylinder large-piece arguments readback"},
                                          MemoryUsage::Readback);
    }

    void upload_geometry() {
        std::vector<glm::vec4> points(positions.size() / 3);
        for (std::size_t v = 0; v < points.size(); ++v)
            points[v] = {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2], 0.0f};
        std::vector<glm::uvec4> faces(triangles.size() / 3);
        for (std::size_t f = 0; f < faces.size(); ++f)
            faces[f] = {triangles[3 * f], triangles[3 * f + 1], triangles[3 * f + 2], 0u};
        positions_img = upload_texel_array(ctx, std::move(points), Format::RGBA32F, "cylinder positions");
        triangles_img = upload_texel_array(ctx, std::move(faces), Format::RGBA32U, "cylinder triangles");
        geometry_dirty = false;
        plan.reset();
    }

    void reserve(std::uint32_t jobs, std::uint64_t faces) {
        const std::uint64_t rects = std::max<std::uint64_t>(GIMG_CYL_RECTS_PER_FACE * faces, 1);
        if (jobs <= job_capacity && rects <= rect_capacity && plan) return;
        const std::uint32_t max_dim = ctx.device_info().max_image_dimension_2d;
        tiles_per_row = std::max(1u, max_dim / width);
        if (jobs > job_capacity) job_capacity = std::max(jobs, 2 * job_capacity);
        const std::uint32_t columns = std::min(job_capacity, tiles_per_row);
        const std::uint32_t rows = (job_capacity + tiles_per_row - 1) / tiles_per_row;
        if (std::uint64_t(rows) * height > max_dim)
            throw geo::InputError("a batch of " + std::to_string(jobs) + " images of " +
                                                        std::to_string(width) + "x" + std::to_string(height) +
                                                        " does not fit one atlas; project fewer at a time");
        if (rects > rect_capacity)
            rect_capacity = std::uint32_t(std::min<std::uint64_t>(std::max<std::uint64_t>(rects, 2ull * rect_capacity), UINT32_MAX));
        const VkDeviceSize rect_bytes = VkDeviceSize(rect_capacity) * 16;
        if (rect_bytes > ctx.device_info().max_storage_buffer_range)
            throw geo::InputError("too many faces in one batch for this device (" +
                                                        std::to_string(faces) + "); project fewer at a time");
        jobs_img = ctx.create_image(texel_array_desc(std::size_t(job_capacity) * kTexelsPerJob, Format::RGBA32U,
                                                            "cylinder job texels"));
        jobs_upload = ctx.create_buffer({jobs_img.byte_size(), "cylinder jobs upload"}, MemoryUsage::Upload);
        jobs_buf = ctx.create_buffer({VkDeviceSize(job_capacity) * sizeof(JobGpu), "cylinder jobs"});
        rects_buf = ctx.create_buffer({rect_bytes, "cylinder rectangles"});
        atlas_width = columns * width;
        atlas_height = rows * height;
        const VkDeviceSize atlas_bytes = VkDeviceSize(atlas_width) * atlas_height * 4;
        keys_buf = ctx.create_buffer({atlas_bytes, "cylinder distance keys"});
        keys_readback = ctx.create_buffer({atlas_bytes, "cylinder distance keys readback"}, MemoryUsage::Readback);
        if (graphics) {
            atlas = ctx.create_image({atlas_width, atlas_height, Format::R32F, "cylinder atlas"});
            atlas_readback = ctx.create_buffer({atlas_bytes, "cylinder atlas readback"}, MemoryUsage::Readback);
        }
        build_plan();
    }

    void build_plan() {
        Graph g(ctx);
        auto pos = g.import_image(positions_img), tri = g.import_image(triangles_img);
        auto jobs_in = g.import_buffer(jobs_upload), jobs = g.import_buffer(jobs_buf);
        auto job_texels = g.import_image(jobs_img);
        auto rects = g.import_buffer(rects_buf), args = g.import_buffer(args_buf);
        auto dirs = g.import_image(directions_img);
        auto keys = g.import_buffer(keys_buf);
        auto keys_out = g.import_buffer(keys_readback), args_out = g.import_buffer(args_readback);
        g.add_compute_pass("reset", [&](PassBuilder& b) {
            b.read(jobs_in, Access::TransferSrc);
            if (graphics) jobs = b.write(jobs, Access::TransferDst);  // only the graphics pipeline reads it
            job_texels = b.write(job_texels, Access::TransferDst);
            args = b.write(args, Access::TransferDst);
            keys = b.write(keys, Access::TransferDst);
        }, [this, jobs_in, jobs, job_texels, args, keys](Cmd& c) {
            if (graphics) c.copy(jobs_in, jobs, jobs_buf.size());
            c.copy(jobs_in, job_texels);
            const PieceArgs init{0, 1, 0, 0, 0, 1, 1, 0};
            c.update(args, &init, sizeof init);
            c.fill(keys, 0);
        });
        g.add_compute_pass("classify, split, small pieces", [&](PassBuilder& b) {
            b.read(pos, Access::ComputeRead);
            b.read(tri, Access::ComputeRead);
            b.read(job_texels, Access::ComputeRead);
            b.read(dirs, Access::ComputeRead);
            rects = b.write(rects, Access::ComputeWrite);
            args = b.write(args, Access::ComputeReadWrite);
            keys = b.write(keys, Access::ComputeReadWrite);
        }, [this, pos, tri, job_texels, rects, args, dirs, keys](Cmd& c) {
            const std::uint32_t groups = (classify.total_faces + GIMG_CYL_CLASSIFY_GROUP - 1) / GIMG_CYL_CLASSIFY_GROUP;
            const std::uint32_t gx = std::min(groups, 65535u), gy = (groups + gx - 1) / std::max(gx, 1u);
            c.dispatch(use_double ? kClassify : kClassifyFloat, {gx, gy, 1},
                       {pos, tri, job_texels, rects, args, dirs, keys}, classify);
        });
        std::optional<ImageHandle> image;
        std::optional<BufferHandle> atlas_out;
        if (graphics) {
            image = g.import_image(atlas);
            atlas_out = g.import_buffer(atlas_readback);
            auto depth = g.create_image({atlas_width, atlas_height, Format::D32F, "cylinder depth"});
            g.add_raster_pass("cylindrical z-buffer", [&](PassBuilder& b) {
                b.read(rects, Access::VertexRead);
                b.read(jobs, Access::VertexRead);
                b.read(jobs, Access::FragmentRead);
                b.read(pos, Access::FragmentRead);
                b.read(tri, Access::FragmentRead);
                b.read(dirs, Access::FragmentRead);
                b.read(args, Access::IndirectArgs);
                image = b.color(*image, ClearValue::color(float(GIMG_CYL_EMPTY)));
                depth = b.depth(depth, ClearValue::depth(1.0f));
            }, [this, rects, jobs, pos, tri, dirs, args](Cmd& c) {
                c.draw_indirect(use_double ? kZBuffer : kZBufferFloat, args, 0, 1, {rects, jobs, pos, tri, dirs}, draw);
            });
        } else {
            g.add_compute_pass("large pieces", [&](PassBuilder& b) {
                b.read(pos, Access::ComputeRead);
                b.read(tri, Access::ComputeRead);
                b.read(job_texels, Access::ComputeRead);
                b.read(rects, Access::ComputeRead);
                b.read(args, Access::IndirectArgs);
                b.read(args, Access::ComputeRead);
                b.read(dirs, Access::ComputeRead);
                keys = b.write(keys, Access::ComputeReadWrite);
            }, [this, pos, tri, job_texels, rects, args, dirs, keys](Cmd& c) {
                c.dispatch_indirect(use_double ? kLargePieces : kLargePiecesFloat, args, kDispatchArgsOffset,
                                    {pos, tri, job_texels, rects, args, dirs, keys}, classify);
            });
        }
        g.add_compute_pass("read back", [&](PassBuilder& b) {
            if (image) b.read(*image, Access::TransferSrc);
            b.read(keys, Access::TransferSrc);
            b.read(args, Access::TransferSrc);
            if (atlas_out) atlas_out = b.write(*atlas_out, Access::TransferDst);
            keys_out = b.write(keys_out, Access::TransferDst);
            args_out = b.write(args_out, Access::TransferDst);
        }, [image, keys, args, atlas_out, keys_out, args_out](Cmd& c) {
            if (image) c.copy(*image, *atlas_out);
            c.copy(keys, keys_out);
            c.copy(args, args_out);
        });
        if (atlas_out) g.export_buffer(*atlas_out, Access::HostRead);
        g.export_buffer(keys_out, Access::HostRead);
        g.export_buffer(args_out, Access::HostRead);
        plan = g.compile();
    }
};

CylinderZBuffer::CylinderZBuffer(Context& ctx, std::uint32_t width, std::uint32_t height,
                                 const CylinderZBufferOptions& options) {
    if (width == 0 || height == 0 || width > 65535 || height > 65535)
        throw geo::InputError("cylinder image size must be between 1x1 and 65535x65535");
    state_ = std::make_unique<State>(ctx, width, height, options);
}

CylinderZBuffer::~CylinderZBuffer() = default;

bool CylinderZBuffer::double_precision() const { return state_->use_double; }

bool CylinderZBuffer::graphics_pipeline() const { return state_->graphics; }

std::vector<PassTiming> CylinderZBuffer::last_pass_timings() const {
    if (!state_->plan || !state_->timestamps) return {};
    return state_->plan->timings();
}

std::uint32_t CylinderZBuffer::add_mesh(const CylinderMesh& mesh) {
    State& s = *state_;
    if (mesh.triangles.size() % 3 != 0 || mesh.positions.size() % 3 != 0)
        throw geo::InputError("cylinder mesh arrays are not whole triangles / vertices");
    const std::uint32_t vertices = std::uint32_t(mesh.positions.size() / 3);
    for (std::uint32_t i : mesh.triangles)
        if (i >= vertices) throw geo::InputError("cylinder mesh face names a missing vertex");
    s.meshes.push_back({std::uint32_t(s.positions.size() / 3), std::uint32_t(s.triangles.size() / 3),
                        std::uint32_t(mesh.face_count())});
    s.positions.insert(s.positions.end(), mesh.positions.begin(), mesh.positions.end());
    // Faces along a Morton curve through their centres: the faces a subgroup classifies together
    // then lie side by side, so their pixels share cache lines and their pixel counts are alike
    // (lanes wait less for the subgroup's largest face). On bunny at 540x270, 6.0 -> 5.4 ms an image
    // on lavapipe. The image does not depend on the order.
    std::vector<glm::dvec3> centres(mesh.face_count(), glm::dvec3(0.0));
    for (std::size_t f = 0; f < centres.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.triangles[3 * f + k];
            centres[f] += glm::dvec3(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]) / 3.0;
        }
    const std::vector<std::uint32_t> order = geo::morton_order(centres, kFaceOrderBitsPerAxis);
    const std::size_t first = s.triangles.size();
    s.triangles.resize(first + mesh.triangles.size());
    for (std::size_t k = 0; k < order.size(); ++k)
        std::copy_n(mesh.triangles.begin() + 3 * std::size_t(order[k]), 3, s.triangles.begin() + first + 3 * k);
    s.geometry_dirty = true;
    return std::uint32_t(s.meshes.size() - 1);
}

std::vector<CylinderImage> CylinderZBuffer::project(std::span<const Job> jobs) {
    State& s = *state_;
    if (jobs.empty()) return {};
    if (s.geometry_dirty) s.upload_geometry();
    for (const Job& j : jobs)
        if (j.mesh >= s.meshes.size()) throw Error(ErrorKind::InvalidArgument, "project(): unknown mesh id");
    // As many images per execution as the rectangle buffer (bound whole, so within
    // maxStorageBufferRange) and one atlas can hold; larger batches run as several executions.
    const std::uint64_t max_faces = s.ctx.device_info().max_storage_buffer_range / (16ull * GIMG_CYL_RECTS_PER_FACE);
    const std::uint32_t max_dim = s.ctx.device_info().max_image_dimension_2d;
    const std::uint64_t max_images = std::uint64_t(std::max(1u, max_dim / s.width)) * std::max(1u, max_dim / s.height);
    std::vector<CylinderImage> out;
    out.reserve(jobs.size());
    double gpu_ms = 0.0;
    std::uint64_t rects = 0;
    for (std::size_t begin = 0; begin < jobs.size();) {
        std::size_t end = begin;
        std::uint64_t faces = 0;
        while (end < jobs.size() && end - begin < max_images &&
               (end == begin || faces + s.meshes[jobs[end].mesh].face_count <= max_faces))
            faces += s.meshes[jobs[end++].mesh].face_count;
        if (faces > max_faces)
            throw geo::InputError("a mesh of " + std::to_string(faces) +
                                                        " faces is more than this device can project at once (" +
                                                        std::to_string(max_faces) + ")");
        auto images = project_batch(jobs.subspan(begin, end - begin), faces);
        for (auto& img : images) out.push_back(std::move(img));
        gpu_ms += last_gpu_ms_;
        rects += last_rects_;
        begin = end;
    }
    last_gpu_ms_ = gpu_ms;
    last_rects_ = rects;
    return out;
}

std::vector<CylinderImage> CylinderZBuffer::project_batch(std::span<const Job> jobs, std::uint64_t total) {
    State& s = *state_;
    s.reserve(std::uint32_t(jobs.size()), total);

    std::vector<JobGpu> gpu(jobs.size());
    std::uint32_t prefix = 0;
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        const MeshRange& m = s.meshes[jobs[k].mesh];
        JobGpu& g = gpu[k];
        std::memcpy(g.rows, jobs[k].transform.data(), sizeof g.rows);
        g.first_face = m.first_face;
        g.face_count = m.face_count;
        g.face_prefix = prefix;
        g.vertex_offset = m.vertex_offset;
        g.tile_x = std::uint32_t(k % s.tiles_per_row) * s.width;
        g.tile_y = std::uint32_t(k / s.tiles_per_row) * s.height;
        g.pad0 = g.pad1 = 0;
        prefix += m.face_count;
    }
    s.ctx.upload(s.jobs_upload, gpu.data(), gpu.size() * sizeof(JobGpu));
    s.classify = {std::uint32_t(total), std::uint32_t(jobs.size()), s.width,         s.height,
                  s.rect_capacity,       s.small_pixels,              s.atlas_width};
    s.draw = {{float(s.atlas_width), float(s.atlas_height)}, {s.width, s.height}};
    s.plan->execute({.wait = true, .timestamps = s.timestamps});
    last_gpu_ms_ = s.timestamps ? s.plan->total_gpu_ms() : 0.0;

    PieceArgs args{};
    s.ctx.download(s.args_readback, &args, sizeof args);
    last_rects_ = args.rect_count;
    const std::size_t atlas_pixels = std::size_t(s.atlas_width) * s.atlas_height;
    std::vector<std::uint32_t> keys(atlas_pixels);
    s.ctx.download(s.keys_readback, keys.data(), atlas_pixels * 4);
    std::vector<float> atlas;
    if (s.graphics) {
        atlas.resize(atlas_pixels);
        s.ctx.download(s.atlas_readback, atlas.data(), atlas_pixels * 4);
    }
    std::vector<CylinderImage> out;
    out.reserve(jobs.size());
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        CylinderImage img(s.width, s.height);
        for (std::uint32_t v = 0; v < s.height; ++v)
            for (std::uint32_t u = 0; u < s.width; ++u) {
                const std::size_t i = std::size_t(gpu[k].tile_y + v) * s.atlas_width + gpu[k].tile_x + u;
                // The larger of the compute passes' t (key 0: none) and the graphics pipeline's (empty: -4).
                float d = keys[i] != 0 ? key_distance(keys[i]) : float(GIMG_CYL_EMPTY);
                if (s.graphics) d = std::max(d, atlas[i]);
                const bool hit = d >= -1.0f;
                img.covered[img.index(u, v)] = hit;
                img.distance[img.index(u, v)] = hit ? d : 0.0f;
            }
        out.push_back(std::move(img));
    }
    return out;
}

CylinderImage CylinderZBuffer::project(std::uint32_t mesh, const CylinderTransform& transform) {
    const Job job{mesh, transform};
    return std::move(project(std::span<const Job>(&job, 1)).front());
}

}  // namespace gimg::passes

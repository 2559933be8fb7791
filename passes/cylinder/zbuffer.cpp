// The GPU cylindrical Z-buffer: classify + split + small pieces (compute), large pieces (the
// graphics pipeline's curved raster, or a compute pass on CPU devices), one graph.
#include "gimg/passes/cylinder.h"
#include "gimg/geometry/error.h"

#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/geometry/vertex_order.h"

#include "gimg/engine/texel_array.h"

#include "cylinder/atlas_images_comp.h"
#include "cylinder/atlas_images_raster_comp.h"
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
const Spirv kAtlasImages = GIMG_SPIRV(gimg_spv_cylinder_atlas_images_comp);
const Spirv kAtlasImagesRaster = GIMG_SPIRV(gimg_spv_cylinder_atlas_images_raster_comp);
const RasterState kDepthMax{
    .cull = CullMode::None, .depth_test = true, .depth_write = true, .depth_compare = CompareOp::Less};
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

// Blocks of the job table for `faces` faces (job_texels.glsl: four a texel, after the jobs).
std::size_t job_blocks(std::uint64_t faces) {
    return std::size_t((faces + GIMG_CYL_JOB_BLOCK - 1) / GIMG_CYL_JOB_BLOCK);
}

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
struct AtlasImagesPush {  // shaders/cylinder/atlas_images_body.glsl
    std::uint32_t width, height, count, tiles_per_row, atlas_width;
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

// Faces or vertices per chunk when a mesh's arrays are filled on every core.
constexpr std::size_t kPackGrain = 1 << 15;

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

namespace {

// The uploaded meshes: one texel a vertex and a face (texel_array.h: lavapipe gathers from images).
// Plans hold it by shared_ptr, so adding a mesh later leaves recorded plans intact.
struct Geometry {
    Image positions, triangles;
};

// One execution's jobs and the atlas they are laid out in: what the recorded passes read each time
// they run. The host writes the jobs into `jobs_upload` before an execution.
struct Batch {
    Buffer jobs_upload;
    std::uint32_t job_capacity = 0, rect_capacity = 0, tiles_per_row = 1, atlas_width = 0, atlas_height = 0;
    std::size_t job_texels = 0;  // the jobs and the job table
    ClassifyPush classify{};
    DrawPush draw{};
};

// What record_projection leaves in the graph: per atlas pixel the compute passes' largest t as an
// ordered key (0: none), the large-piece arguments, and with the graphics pipeline its t per pixel.
struct Projection {
    BufferHandle keys, args;
    std::optional<ImageHandle> raster_t;
};

}  // namespace

struct CylinderZBuffer::State {
    Context& ctx;
    std::uint32_t width, height, small_pixels;
    bool use_double, timestamps;
    bool graphics;  // large pieces through the graphics pipeline (else large_pieces.comp)

    // Every mesh's vertices and faces as the texels they are uploaded as, added one after another.
    std::vector<glm::vec4> point_texels;
    std::vector<glm::uvec4> face_texels;
    std::vector<MeshRange> meshes;
    std::shared_ptr<Geometry> geometry;  // null until the meshes are uploaded
    std::shared_ptr<Image> directions;   // texel u: cos and sin of theta_u

    // project()'s own plan: the batch it reads, and where it copies the keys, the graphics
    // pipeline's t and the arguments for the host, which merges them as it unpacks the images (on
    // lavapipe a merge pass cost about 0.35 ms an image).
    std::shared_ptr<Batch> batch;
    Buffer keys_readback, raster_readback, args_readback;
    std::optional<Plan> plan;

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
        directions =
            std::make_shared<Image>(upload_texel_array(ctx, std::move(texels), Format::RGBA32U, "cylinder directions"));
        args_readback =
            ctx.create_buffer({sizeof(PieceArgs), "cylinder large-piece arguments readback"}, MemoryUsage::Readback);
    }

    const Geometry& uploaded_geometry() {
        if (geometry) return *geometry;
        geometry = std::make_shared<Geometry>();
        ctx.batch_uploads([&] {  // one submission for the two
            geometry->positions = upload_texel_array(ctx, std::span<const glm::vec4>(point_texels), Format::RGBA32F,
                                                     "cylinder positions");
            geometry->triangles = upload_texel_array(ctx, std::span<const glm::uvec4>(face_texels), Format::RGBA32U,
                                                     "cylinder triangles");
        });
        plan.reset();
        return *geometry;
    }

    // The most faces one execution can take (the rectangle buffer is bound whole, so it stays
    // within maxStorageBufferRange) and the most images one atlas holds.
    std::uint64_t max_faces() const {
        return ctx.device_info().max_storage_buffer_range / (16ull * GIMG_CYL_RECTS_PER_FACE);
    }
    std::uint64_t max_images() const {
        const std::uint32_t max_dim = ctx.device_info().max_image_dimension_2d;
        return std::uint64_t(std::max(1u, max_dim / width)) * std::max(1u, max_dim / height);
    }

    // A batch for up to `jobs` images and `faces` faces, laid out in one atlas.
    std::shared_ptr<Batch> make_batch(std::uint32_t jobs, std::uint64_t faces) const {
        auto b = std::make_shared<Batch>();
        const std::uint32_t max_dim = ctx.device_info().max_image_dimension_2d;
        b->job_capacity = std::max(jobs, 1u);
        b->tiles_per_row = std::max(1u, max_dim / width);
        const std::uint32_t columns = std::min(b->job_capacity, b->tiles_per_row);
        const std::uint32_t rows = (b->job_capacity + b->tiles_per_row - 1) / b->tiles_per_row;
        if (std::uint64_t(rows) * height > max_dim)
            throw geo::InputError("a batch of " + std::to_string(jobs) + " images of " + std::to_string(width) + "x" +
                                  std::to_string(height) + " does not fit one atlas; project fewer at a time");
        const std::uint64_t rects = std::max<std::uint64_t>(GIMG_CYL_RECTS_PER_FACE * faces, 1);
        b->rect_capacity = std::uint32_t(std::min<std::uint64_t>(rects, UINT32_MAX));
        if (VkDeviceSize(b->rect_capacity) * 16 > ctx.device_info().max_storage_buffer_range)
            throw geo::InputError("too many faces in one batch for this device (" + std::to_string(faces) +
                                  "); project fewer at a time");
        b->atlas_width = columns * width;
        b->atlas_height = rows * height;
        // The job table sits right after the batch's jobs: room for it after every job slot.
        b->job_texels = std::size_t(b->job_capacity) * kTexelsPerJob +
                        (job_blocks(b->rect_capacity / GIMG_CYL_RECTS_PER_FACE) + 3) / 4;
        const ImageDesc texels = texel_array_desc(b->job_texels, Format::RGBA32U, "");
        b->jobs_upload = ctx.create_buffer({VkDeviceSize(texels.width) * texels.height * 16, "cylinder jobs upload"},
                                           MemoryUsage::Upload);
        return b;
    }

    // Writes the jobs into the batch (tiles in atlas order) and returns them as the shaders see them.
    std::vector<JobGpu> write_jobs(Batch& b, std::span<const Job> jobs, std::uint64_t faces) const {
        std::vector<JobGpu> gpu(jobs.size());
        std::uint32_t prefix = 0;
        for (std::size_t k = 0; k < jobs.size(); ++k) {
            const MeshRange& m = meshes[jobs[k].mesh];
            JobGpu& g = gpu[k];
            std::memcpy(g.rows, jobs[k].transform.data(), sizeof g.rows);
            g.first_face = m.first_face;
            g.face_count = m.face_count;
            g.face_prefix = prefix;
            g.vertex_offset = m.vertex_offset;
            g.tile_x = std::uint32_t(k % b.tiles_per_row) * width;
            g.tile_y = std::uint32_t(k / b.tiles_per_row) * height;
            g.pad0 = g.pad1 = 0;
            prefix += m.face_count;
        }
        // The job table: per block, job_of of its first face (the last job whose prefix <= it).
        std::vector<std::uint32_t> table(job_blocks(faces));
        for (std::size_t block = 0, k = 0; block < table.size(); ++block) {
            while (k + 1 < gpu.size() && gpu[k + 1].face_prefix <= block * GIMG_CYL_JOB_BLOCK) ++k;
            table[block] = std::uint32_t(k);
        }
        ctx.upload(b.jobs_upload, gpu.data(), gpu.size() * sizeof(JobGpu));
        ctx.upload(b.jobs_upload, table.data(), table.size() * 4, gpu.size() * sizeof(JobGpu));
        b.classify = {std::uint32_t(faces), std::uint32_t(jobs.size()), width, height, b.rect_capacity, small_pixels,
                      b.atlas_width};
        b.draw = {{float(b.atlas_width), float(b.atlas_height)}, {width, height}};
        return gpu;
    }

    // Records reset, classify + small pieces and the large-piece pass of one batch into g. The
    // passes read the batch, the geometry and the directions through shared ownership or imports.
    Projection record_projection(Graph& g, const std::shared_ptr<Batch>& bt, const std::string& name) {
        const auto geo_ptr = geometry;
        const auto dirs_ptr = directions;
        auto pos = g.import_image(geo_ptr->positions), tri = g.import_image(geo_ptr->triangles);
        auto dirs = g.import_image(*dirs_ptr);
        auto jobs_in = g.import_buffer(bt->jobs_upload);
        auto job_texels = g.create_image(texel_array_desc(bt->job_texels, Format::RGBA32U, name + " job texels"));
        const VkDeviceSize jobs_bytes = VkDeviceSize(bt->job_capacity) * sizeof(JobGpu);
        auto jobs = g.create_buffer({jobs_bytes, name + " jobs"});
        auto rects = g.create_buffer({VkDeviceSize(bt->rect_capacity) * 16, name + " rectangles"});
        auto args = g.create_buffer({sizeof(PieceArgs), name + " large-piece arguments"});
        auto keys = g.create_buffer({VkDeviceSize(bt->atlas_width) * bt->atlas_height * 4, name + " distance keys"});
        const bool graphics_pass = graphics, dbl = use_double;
        g.add_compute_pass(
            name + ": reset",
            [&](PassBuilder& b) {
                b.read(jobs_in, Access::TransferSrc);
                if (graphics_pass) jobs = b.write(jobs, Access::TransferDst);  // only the graphics pipeline reads it
                job_texels = b.write(job_texels, Access::TransferDst);
                args = b.write(args, Access::TransferDst);
                keys = b.write(keys, Access::TransferDst);
            },
            [graphics_pass, jobs_bytes, jobs_in, jobs, job_texels, args, keys, bt](Cmd& c) {
                if (graphics_pass) c.copy(jobs_in, jobs, jobs_bytes);
                c.copy(jobs_in, job_texels);
                const PieceArgs init{0, 1, 0, 0, 0, 1, 1, 0};
                c.update(args, &init, sizeof init);
                c.fill(keys, 0);
            });
        g.add_compute_pass(
            name + ": classify, split, small pieces",
            [&](PassBuilder& b) {
                b.read(pos, Access::ComputeRead);
                b.read(tri, Access::ComputeRead);
                b.read(job_texels, Access::ComputeRead);
                b.read(dirs, Access::ComputeRead);
                rects = b.write(rects, Access::ComputeWrite);
                args = b.write(args, Access::ComputeReadWrite);
                keys = b.write(keys, Access::ComputeReadWrite);
            },
            [dbl, bt, geo_ptr, dirs_ptr, pos, tri, job_texels, rects, args, dirs, keys](Cmd& c) {
                const std::uint32_t groups =
                    (bt->classify.total_faces + GIMG_CYL_CLASSIFY_GROUP - 1) / GIMG_CYL_CLASSIFY_GROUP;
                const std::uint32_t gx = std::min(groups, 65535u), gy = (groups + gx - 1) / std::max(gx, 1u);
                c.dispatch(dbl ? kClassify : kClassifyFloat, {gx, gy, 1},
                           {pos, tri, job_texels, rects, args, dirs, keys}, bt->classify);
            });
        Projection out{keys, args, std::nullopt};
        if (graphics_pass) {
            auto raster_t = g.create_image({bt->atlas_width, bt->atlas_height, Format::R32F, name + " atlas"});
            auto depth = g.create_image({bt->atlas_width, bt->atlas_height, Format::D32F, name + " depth"});
            g.add_raster_pass(
                name + ": z-buffer",
                [&](PassBuilder& b) {
                    b.read(rects, Access::VertexRead);
                    b.read(jobs, Access::VertexRead);
                    b.read(jobs, Access::FragmentRead);
                    b.read(pos, Access::FragmentRead);
                    b.read(tri, Access::FragmentRead);
                    b.read(dirs, Access::FragmentRead);
                    b.read(args, Access::IndirectArgs);
                    raster_t = b.color(raster_t, ClearValue::color(float(GIMG_CYL_EMPTY)));
                    depth = b.depth(depth, ClearValue::depth(1.0f));
                },
                [dbl, bt, geo_ptr, rects, jobs, pos, tri, dirs, args](Cmd& c) {
                    c.draw_indirect(dbl ? kZBuffer : kZBufferFloat, args, 0, 1, {rects, jobs, pos, tri, dirs},
                                    bt->draw);
                });
            out.raster_t = raster_t;
        } else {
            g.add_compute_pass(
                name + ": large pieces",
                [&](PassBuilder& b) {
                    b.read(pos, Access::ComputeRead);
                    b.read(tri, Access::ComputeRead);
                    b.read(job_texels, Access::ComputeRead);
                    b.read(rects, Access::ComputeRead);
                    b.read(args, Access::IndirectArgs);
                    b.read(args, Access::ComputeRead);
                    b.read(dirs, Access::ComputeRead);
                    keys = b.write(keys, Access::ComputeReadWrite);
                },
                [dbl, bt, geo_ptr, pos, tri, job_texels, rects, args, dirs, keys](Cmd& c) {
                    c.dispatch_indirect(dbl ? kLargePieces : kLargePiecesFloat, args, kDispatchArgsOffset,
                                        {pos, tri, job_texels, rects, args, dirs, keys}, bt->classify);
                });
            out.keys = keys;
        }
        return out;
    }

    // project()'s plan, rebuilt when a batch outgrows it or the meshes change.
    void reserve(std::uint32_t jobs, std::uint64_t faces) {
        uploaded_geometry();
        const std::uint32_t have_jobs = batch ? batch->job_capacity : 0;
        const std::uint64_t have_faces = batch ? batch->rect_capacity / GIMG_CYL_RECTS_PER_FACE : 0;
        if (plan && jobs <= have_jobs && faces <= have_faces) return;
        // What outgrows the plan grows to twice the old size (within the device's limits), so a
        // growing series of batches rebuilds it rarely.
        const auto grow = [](std::uint64_t need, std::uint64_t have, std::uint64_t limit) {
            return need <= have ? have : std::max(need, std::min(2 * have, limit));
        };
        plan.reset();
        batch = make_batch(std::uint32_t(grow(jobs, have_jobs, max_images())), grow(faces, have_faces, max_faces()));
        const VkDeviceSize atlas_bytes = VkDeviceSize(batch->atlas_width) * batch->atlas_height * 4;
        keys_readback = ctx.create_buffer({atlas_bytes, "cylinder distance keys readback"}, MemoryUsage::Readback);
        if (graphics)
            raster_readback = ctx.create_buffer({atlas_bytes, "cylinder atlas readback"}, MemoryUsage::Readback);

        Graph g(ctx);
        const Projection p = record_projection(g, batch, "cylinder");
        auto keys_out = g.import_buffer(keys_readback), args_out = g.import_buffer(args_readback);
        std::optional<BufferHandle> raster_out;
        if (graphics) raster_out = g.import_buffer(raster_readback);
        g.add_compute_pass(
            "cylinder: read back",
            [&](PassBuilder& b) {
                if (p.raster_t) b.read(*p.raster_t, Access::TransferSrc);
                b.read(p.keys, Access::TransferSrc);
                b.read(p.args, Access::TransferSrc);
                if (raster_out) raster_out = b.write(*raster_out, Access::TransferDst);
                keys_out = b.write(keys_out, Access::TransferDst);
                args_out = b.write(args_out, Access::TransferDst);
            },
            [p, raster_out, keys_out, args_out](Cmd& c) {
                if (p.raster_t) c.copy(*p.raster_t, *raster_out);
                c.copy(p.keys, keys_out);
                c.copy(p.args, args_out);
            });
        if (raster_out) g.export_buffer(*raster_out, Access::HostRead);
        g.export_buffer(keys_out, Access::HostRead);
        g.export_buffer(args_out, Access::HostRead);
        plan = g.compile();
    }
};

CylinderZBuffer::CylinderZBuffer(Context& ctx, std::uint32_t width, std::uint32_t height,
                                 const CylinderZBufferOptions& options) {
    if (width == 0 || height == 0 || width > 65535 || height > 65535)
        throw geo::InputError("cylinder image size must be between 1x1 and 65535x65535");
    // The atlas's keys are one storage buffer, bound whole: the device's binding range caps the pixels.
    const std::uint64_t max_pixels = ctx.device_info().max_storage_buffer_range / 4;
    if (std::uint64_t(width) * height > max_pixels || width > ctx.device_info().max_image_dimension_2d ||
        height > ctx.device_info().max_image_dimension_2d)
        throw geo::InputError("a " + std::to_string(width) + "x" + std::to_string(height) +
                              " cylindrical image is more than this device projects at once (at most " +
                              std::to_string(max_pixels) + " pixels, sides up to " +
                              std::to_string(ctx.device_info().max_image_dimension_2d) +
                              "); use a smaller --size or --method scanline");
    state_ = std::make_unique<State>(ctx, width, height, options);
}

CylinderZBuffer::~CylinderZBuffer() = default;

bool CylinderZBuffer::double_precision() const { return state_->use_double; }

bool CylinderZBuffer::graphics_pipeline() const { return state_->graphics; }

std::vector<PassTiming> CylinderZBuffer::last_pass_timings() const {
    if (!state_->plan || !state_->timestamps) return {};
    return state_->plan->timings();
}

void CylinderZBuffer::reserve(std::size_t vertices, std::size_t faces) {
    state_->point_texels.reserve(state_->point_texels.size() + vertices);
    state_->face_texels.reserve(state_->face_texels.size() + faces);
}

namespace {

// The faces along a Morton curve through their centres: the faces a subgroup classifies together
// then lie side by side, so their pixels share cache lines and their pixel counts are alike (lanes
// wait less for the subgroup's largest face). On bunny at 540x270, 6.0 -> 5.4 ms an image on
// lavapipe. The image does not depend on the order. (Sums of the corners, not their means: the
// curve is the same at any scale.)
std::vector<std::uint32_t> face_order(const CylinderMesh& mesh) {
    if (mesh.triangles.size() % 3 != 0 || mesh.positions.size() % 3 != 0)
        throw geo::InputError("cylinder mesh arrays are not whole triangles / vertices");
    const std::uint32_t vertices = std::uint32_t(mesh.positions.size() / 3);
    std::vector<glm::dvec3> centres(mesh.face_count(), glm::dvec3(0.0));
    geo::parallel_for_chunks(centres.size(), kPackGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t f = begin; f < end; ++f)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = mesh.triangles[3 * f + k];
                if (v >= vertices) throw geo::InputError("cylinder mesh face names a missing vertex");
                centres[f] += glm::dvec3(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
            }
    });
    return geo::morton_order(centres, kFaceOrderBitsPerAxis);
}

}  // namespace

std::uint32_t CylinderZBuffer::add_mesh(const CylinderMesh& mesh) { return add_meshes({&mesh, 1}).front(); }

std::vector<std::uint32_t> CylinderZBuffer::add_meshes(std::span<const CylinderMesh> meshes) {
    State& s = *state_;
    // The orders on every core (the checks with them), then the texels one mesh after another.
    std::vector<std::vector<std::uint32_t>> orders(meshes.size());
    geo::parallel_for_chunks(meshes.size(), 1, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) orders[i] = face_order(meshes[i]);
    });
    std::vector<std::uint32_t> ids;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const CylinderMesh& mesh = meshes[i];
        const std::size_t first_point = s.point_texels.size(), first_face = s.face_texels.size();
        s.meshes.push_back({std::uint32_t(first_point), std::uint32_t(first_face), std::uint32_t(mesh.face_count())});
        s.point_texels.resize(first_point + mesh.positions.size() / 3);
        s.face_texels.resize(first_face + orders[i].size());
        glm::vec4* points = s.point_texels.data() + first_point;
        glm::uvec4* faces = s.face_texels.data() + first_face;
        geo::parallel_for_chunks(
            mesh.positions.size() / 3, kPackGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
                for (std::size_t v = begin; v < end; ++v)
                    points[v] = {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2], 0.0f};
            });
        geo::parallel_for_chunks(orders[i].size(), kPackGrain, [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                const std::size_t f = orders[i][k];
                faces[k] = {mesh.triangles[3 * f], mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2], 0u};
            }
        });
        ids.push_back(std::uint32_t(s.meshes.size() - 1));
    }
    s.geometry.reset();
    return ids;
}

std::vector<CylinderImage> CylinderZBuffer::project(std::span<const Job> jobs) {
    State& s = *state_;
    if (jobs.empty()) return {};
    for (const Job& j : jobs)
        if (j.mesh >= s.meshes.size()) throw Error(ErrorKind::InvalidArgument, "project(): unknown mesh id");
    // As many images per execution as one plan can hold; larger batches run as several executions.
    const std::uint64_t max_faces = s.max_faces(), max_images = s.max_images();
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
                                  " faces is more than this device can project at once (" + std::to_string(max_faces) +
                                  ")");
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
    const Batch& b = *s.batch;
    const std::vector<JobGpu> gpu = s.write_jobs(*s.batch, jobs, total);
    s.plan->execute({.wait = true, .timestamps = s.timestamps});
    last_gpu_ms_ = s.timestamps ? s.plan->total_gpu_ms() : 0.0;

    PieceArgs args{};
    s.ctx.download(s.args_readback, &args, sizeof args);
    last_rects_ = args.rect_count;
    // Only the atlas rows this batch's tiles fill: a small batch in a large plan reads little.
    const std::size_t tile_rows = (jobs.size() + b.tiles_per_row - 1) / b.tiles_per_row;
    const std::size_t atlas_pixels = std::size_t(b.atlas_width) * tile_rows * s.height;
    std::vector<std::uint32_t> keys(atlas_pixels);
    s.ctx.download(s.keys_readback, keys.data(), atlas_pixels * 4);
    std::vector<float> raster_t;
    if (s.graphics) {
        raster_t.resize(atlas_pixels);
        s.ctx.download(s.raster_readback, raster_t.data(), atlas_pixels * 4);
    }
    std::vector<CylinderImage> out;
    out.reserve(jobs.size());
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        CylinderImage img(s.width, s.height);
        for (std::uint32_t v = 0; v < s.height; ++v)
            for (std::uint32_t u = 0; u < s.width; ++u) {
                const std::size_t i = std::size_t(gpu[k].tile_y + v) * b.atlas_width + gpu[k].tile_x + u;
                // The larger of the compute passes' t (key 0: none) and the graphics pipeline's
                // (empty: -4); shaders/cylinder/atlas_images_body.glsl decides the same on the GPU.
                float d = keys[i] != 0 ? key_distance(keys[i]) : float(GIMG_CYL_EMPTY);
                if (s.graphics) d = std::max(d, raster_t[i]);
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

CylinderImagesHandle add_cylinder(Graph& graph, CylinderZBuffer& zbuffer, std::span<const CylinderZBuffer::Job> jobs,
                                  const std::string& name) {
    CylinderZBuffer::State& s = *zbuffer.state_;
    if (jobs.empty()) throw geo::InputError("add_cylinder: no images to project");
    std::uint64_t faces = 0;
    for (const CylinderZBuffer::Job& j : jobs) {
        if (j.mesh >= s.meshes.size()) throw geo::InputError("add_cylinder: unknown mesh id " + std::to_string(j.mesh));
        faces += s.meshes[j.mesh].face_count;
    }
    if (faces > s.max_faces() || jobs.size() > s.max_images())
        throw geo::InputError("add_cylinder: " + std::to_string(jobs.size()) + " images of " + std::to_string(faces) +
                              " faces in all are more than one execution holds on this device (" +
                              std::to_string(s.max_images()) + " images, " + std::to_string(s.max_faces()) +
                              " faces); record fewer at a time");
    const VkDeviceSize image_bytes = VkDeviceSize(jobs.size()) * s.width * s.height * 4;
    if (image_bytes > s.ctx.device_info().max_storage_buffer_range)
        throw geo::InputError("add_cylinder: " + std::to_string(jobs.size()) + " images of " + std::to_string(s.width) +
                              "x" + std::to_string(s.height) +
                              " are more than one buffer holds on this device; record fewer at a time");
    s.uploaded_geometry();
    auto batch = s.make_batch(std::uint32_t(jobs.size()), faces);
    s.write_jobs(*batch, jobs, faces);
    const Projection p = s.record_projection(graph, batch, name);

    auto images = graph.create_buffer({image_bytes, name + " images"});
    const AtlasImagesPush push{s.width, s.height, std::uint32_t(jobs.size()), batch->tiles_per_row, batch->atlas_width};
    graph.add_compute_pass(
        name + ": images",
        [&](PassBuilder& b) {
            b.read(p.keys, Access::ComputeRead);
            if (p.raster_t) b.read(*p.raster_t, Access::ComputeRead);
            images = b.write(images, Access::ComputeWrite);
        },
        [p, images, push](Cmd& c) {
            if (p.raster_t)
                c.dispatch_threads(kAtlasImagesRaster, {push.width, push.height, push.count},
                                   {p.keys, images, *p.raster_t}, push);
            else
                c.dispatch_threads(kAtlasImages, {push.width, push.height, push.count}, {p.keys, images}, push);
        });
    return {images, s.width, s.height, std::uint32_t(jobs.size())};
}

}  // namespace gimg::passes

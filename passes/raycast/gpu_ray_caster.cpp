// GpuRayCaster: the BVH's nodes (the builder's array, with skip links) and corners (double) in texel arrays,
// its face order in a storage buffer, and one compute pass (shaders/raycast/raycast.glsl) per call.
#include "gimg/passes/raycast.h"

#include "gimg/engine/error.h"
#include "gimg/engine/texel_array.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/bvh.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"

#include "raycast/raycast_comp.h"
#include "raycast/raycast_plain_comp.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cstring>
#include <span>
#include <stdexcept>

namespace gimg::passes {

namespace {

const Spirv kRaycast = GIMG_SPIRV(gimg_spv_raycast_raycast_comp);
const Spirv kRaycastPlain = GIMG_SPIRV(gimg_spv_raycast_raycast_plain_comp);

struct RaycastPush {
    std::uint32_t count, mode, front_faces_only;
    float scene;
};

// The shader's node texels, written into `out` (2 per node of the builder's array, in its order):
// texel 2k is (lo, the node after k's subtree), 2k + 1 (hi, (first << 3) | count: an inner node's
// first child with count 0, a leaf's first slot). One sweep sets the skip links, since the builder
// places a node's children after it: the first child's skip is its sibling, the second's its parent's.
void node_texels(const geo::BvhNodeArray& nodes, std::span<glm::uvec4> out) {
    const auto end = static_cast<std::uint32_t>(nodes.size());
    out[0].w = end;
    for (std::uint32_t k = 0; k < end; ++k) {
        if (k == 1) {  // the builder's padding node, which no walk reaches
            out[2] = glm::uvec4(0u, 0u, 0u, end);
            out[3] = glm::uvec4(0u);
            continue;
        }
        const geo::BvhNode& nd = nodes[k];
        if (nd.is_leaf() ? nd.count > 7 : nd.first <= k || nd.first + 1 >= end)
            throw std::logic_error(
                "GPU ray casting: a BVH leaf of more than 7 triangles, or a child before its parent");
        if (nd.first >= (1u << 29))
            throw geo::InputError("GPU ray casting: a BVH node the shader cannot address (beyond 2^29)");
        std::memcpy(&out[2 * k], &nd.bounds_min, sizeof nd.bounds_min);
        std::memcpy(&out[2 * k + 1], &nd.bounds_max, sizeof nd.bounds_max);
        out[2 * k + 1].w = (nd.first << 3) | (nd.is_leaf() ? nd.count : 0u);
        if (!nd.is_leaf()) {
            out[2 * nd.first].w = nd.first + 1;
            out[2 * nd.first + 2].w = out[2 * k].w;
        }
    }
}

}  // namespace

struct GpuRayCaster::State {
    Context& ctx;
    Image nodes, corners;  // texel arrays (the shader's header says how)
    Buffer faces;
    float scene = 0.0f;  // geo::bvh_extent of the tree
    bool votes = false;
    bool timestamps = false;
    explicit State(Context& c) : ctx(c) {}
};

GpuRayCaster::GpuRayCaster(Context& ctx, const geo::Mesh& mesh, const GpuRayCasterOptions& options)
    : state_(std::make_unique<State>(ctx)) {
    if (!ctx.device_info().shader_float64)
        throw Error(ErrorKind::Unsupported, "GPU ray casting needs shaderFloat64 (use the CPU ray caster)");
    if (mesh.face_count() == 0) throw geo::InputError("ray casting: the mesh has no faces");
    State& s = *state_;
    s.votes = options.subgroup_votes && ctx.device_info().subgroup_vote;
    s.timestamps = options.timestamps && ctx.device_info().timestamp_period_ns > 0.0;
    // The tree without TriangleBvh's double-precision copy of the triangles: the corners go
    // straight from the mesh into their texel array.
    const geo::BvhLayout tree = geo::build_bvh_layout(mesh);
    s.scene = geo::bvh_extent(tree.nodes);
    // Both arrays are written straight into the images where the device allows, else into the
    // upload's staging memory (Context::create_image; bunny's corners: 6 MB), in one submission.
    ctx.batch_uploads([&] {
        s.nodes = upload_texel_array<glm::uvec4>(ctx, 2 * tree.nodes.size(), Format::RGBA32U, "raycast nodes",
                                                 [&](std::span<glm::uvec4> out) { node_texels(tree.nodes, out); });
        const std::size_t slots = tree.face_order.size();
        s.corners = upload_texel_array<glm::uvec4>(
            ctx, 5 * slots, Format::RGBA32U, "raycast corners", [&](std::span<glm::uvec4> out) {
                geo::parallel_for_chunks(slots, 16384, [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t i = begin; i < end; ++i) {
                        const glm::uvec3& t = mesh.triangles[tree.face_order[i]];
                        const glm::dvec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
                        const double v[10] = {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, 0.0};
                        std::memcpy(&out[5 * i], v, sizeof v);
                    }
                });
            });
        s.faces = upload_buffer(ctx, tree.face_order, "raycast face order");
    });
}

GpuRayCaster::~GpuRayCaster() = default;

RaycastTree import_raycast_tree(Graph& graph, GpuRayCaster& caster) {
    GpuRayCaster::State& s = *caster.state_;
    return {graph.import_image(s.nodes), graph.import_image(s.corners), graph.import_buffer(s.faces), s.scene, s.votes};
}

RaycastHandles add_raycast(Graph& graph, GpuRayCaster& caster, BufferHandle rays, BufferHandle t, BufferHandle face,
                           std::uint32_t count, std::uint32_t mode, bool front_faces_only, const std::string& name) {
    const RaycastTree tree = import_raycast_tree(graph, caster);
    const auto nodes = tree.nodes, tris = tree.corners;
    const auto faces = tree.faces;
    const RaycastPush push{count, mode, front_faces_only ? 1u : 0u, tree.scene};
    const Spirv& kernel = tree.votes ? kRaycast : kRaycastPlain;
    graph.add_compute_pass(
        name,
        [&](PassBuilder& b) {
            b.read(nodes, Access::ComputeRead);
            b.read(tris, Access::ComputeRead);
            for (auto h : {faces, rays}) b.read(h, Access::ComputeRead);
            t = b.write(t, Access::ComputeWrite);
            face = b.write(face, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kernel, {count}, {nodes, tris, faces, rays, t, face}, push);
        });
    return {t, face};
}

std::vector<std::uint32_t> GpuRayCaster::run(std::span<const geo::Ray> rays, std::uint32_t mode,
                                             std::vector<double>* t_out) {
    State& s = *state_;
    if (rays.empty()) return {};
    const bool front = rays.front().front_faces_only;
    for (const geo::Ray& r : rays)
        if (r.front_faces_only != front)
            throw geo::InputError("GpuRayCaster: every ray of one call must have the same front_faces_only");
    std::vector<double> packed(8 * rays.size());
    geo::parallel_for_chunks(rays.size(), 4096, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const geo::Ray& r = rays[i];
            const double v[8] = {r.origin.x,    r.origin.y,    r.origin.z, r.direction.x,
                                 r.direction.y, r.direction.z, r.t_min,    r.t_max};
            std::memcpy(&packed[8 * i], v, sizeof v);
        }
    });
    const auto count = std::uint32_t(rays.size());
    Buffer ray_buf = upload_buffer(s.ctx, packed, "rays");
    Buffer t_buf = s.ctx.create_buffer({VkDeviceSize(count) * 8, "ray t"});
    Buffer face_buf = s.ctx.create_buffer({VkDeviceSize(count) * 4, "ray faces"});
    Graph g(s.ctx);
    const RaycastHandles out = add_raycast(g, *this, g.import_buffer(ray_buf), g.import_buffer(t_buf),
                                           g.import_buffer(face_buf), count, mode, front);
    g.export_buffer(out.t, Access::TransferSrc);
    g.export_buffer(out.face, Access::TransferSrc);
    Plan plan = g.compile();
    plan.execute({.wait = true, .timestamps = s.timestamps});
    last_gpu_ms_ = s.timestamps ? plan.total_gpu_ms() : 0.0;
    std::vector<std::uint32_t> faces(count);
    s.ctx.download(face_buf, faces.data(), faces.size() * 4);
    if (t_out) {
        t_out->resize(count);
        s.ctx.download(t_buf, t_out->data(), t_out->size() * 8);
    }
    return faces;
}

std::vector<GpuRayHit> GpuRayCaster::nearest(std::span<const geo::Ray> rays) {
    std::vector<double> t;
    const std::vector<std::uint32_t> faces = run(rays, 0, &t);
    std::vector<GpuRayHit> out(faces.size());
    for (std::size_t i = 0; i < out.size(); ++i)
        if (faces[i] != 0xffffffffu) out[i] = {t[i], faces[i]};
    return out;
}

std::vector<std::uint32_t> GpuRayCaster::crossings(std::span<const geo::Ray> rays) {
    return run(rays, 1, nullptr);
}

}  // namespace gimg::passes

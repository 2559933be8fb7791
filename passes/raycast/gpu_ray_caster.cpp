// GpuRayCaster: the BVH's nodes and corners (double) in texel arrays, its face order in a storage
// buffer, and one compute pass (shaders/raycast/raycast.comp) per call.
#include "gimg/passes/raycast.h"

#include "gimg/engine/error.h"
#include "gimg/engine/texel_array.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/bvh.h"
#include "gimg/geometry/error.h"

#include "raycast/raycast_comp.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cstring>

namespace gimg::passes {

namespace {

const Spirv kRaycast = GIMG_SPIRV(gimg_spv_raycast_raycast_comp);

struct RaycastPush {
    std::uint32_t count, mode, front_faces_only;
};

}  // namespace

struct GpuRayCaster::State {
    Context& ctx;
    geo::TriangleBvh bvh;
    Image nodes, corners;  // texel arrays (the shader's header says how)
    Buffer faces;
    explicit State(Context& c) : ctx(c) {}
};

GpuRayCaster::GpuRayCaster(Context& ctx, const geo::Mesh& mesh) : state_(std::make_unique<State>(ctx)) {
    if (!ctx.device_info().shader_float64)
        throw Error(ErrorKind::Unsupported, "GPU ray casting needs shaderFloat64 (use the CPU ray caster)");
    if (mesh.face_count() == 0) throw geo::InputError("ray casting: the mesh has no faces");
    State& s = *state_;
    s.bvh = geo::TriangleBvh(mesh);
    const auto& nodes = s.bvh.nodes();
    std::vector<glm::uvec4> node_texels(2 * nodes.size());
    std::memcpy(node_texels.data(), nodes.data(), nodes.size() * sizeof(geo::BvhNode));
    s.nodes = upload_texel_array(ctx, std::move(node_texels), Format::RGBA32U, "raycast nodes");
    std::vector<glm::uvec4> corner_texels(5 * s.bvh.triangles().size(), glm::uvec4(0));
    for (std::size_t i = 0; i < s.bvh.triangles().size(); ++i) {
        const auto& t = s.bvh.triangles()[i];
        const double v[9] = {t.a.x, t.a.y, t.a.z, t.b.x, t.b.y, t.b.z, t.c.x, t.c.y, t.c.z};
        std::memcpy(&corner_texels[5 * i], v, sizeof v);
    }
    s.corners = upload_texel_array(ctx, std::move(corner_texels), Format::RGBA32U, "raycast corners");
    s.faces = upload_buffer(ctx, s.bvh.face_order(), "raycast face order");
}

GpuRayCaster::~GpuRayCaster() = default;

RaycastHandles add_raycast(Graph& graph, GpuRayCaster& caster, BufferHandle rays, BufferHandle t, BufferHandle face,
                           std::uint32_t count, std::uint32_t mode, bool front_faces_only, const std::string& name) {
    GpuRayCaster::State& s = *caster.state_;
    auto nodes = graph.import_image(s.nodes), tris = graph.import_image(s.corners);
    auto faces = graph.import_buffer(s.faces);
    const RaycastPush push{count, mode, front_faces_only ? 1u : 0u};
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
            c.dispatch_threads(kRaycast, {count}, {nodes, tris, faces, rays, t, face}, push);
        });
    return {t, face};
}

std::vector<std::uint32_t> GpuRayCaster::run(std::span<const geo::Ray> rays, std::uint32_t mode,
                                             std::vector<double>* t_out) {
    State& s = *state_;
    if (rays.empty()) return {};
    const bool front = rays.front().front_faces_only;
    std::vector<double> packed(8 * rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const geo::Ray& r = rays[i];
        if (r.front_faces_only != front)
            throw geo::InputError("GpuRayCaster: every ray of one call must have the same front_faces_only");
        const double v[8] = {r.origin.x,    r.origin.y,    r.origin.z, r.direction.x,
                             r.direction.y, r.direction.z, r.t_min,    r.t_max};
        std::memcpy(&packed[8 * i], v, sizeof v);
    }
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
    const bool timed = s.ctx.device_info().timestamp_period_ns > 0.0;
    plan.execute({.wait = true, .timestamps = timed});
    last_gpu_ms_ = timed ? plan.total_gpu_ms() : 0.0;
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
    std::vector<std::uint32_t> counts = run(rays, 1, nullptr);
    // Rays with more hits than the pass keeps: counted on the host, by the same rule.
    for (std::size_t i = 0; i < counts.size(); ++i)
        if (counts[i] == 0xffffffffu) counts[i] = state_->bvh.crossings(rays[i]);
    return counts;
}

}  // namespace gimg::passes

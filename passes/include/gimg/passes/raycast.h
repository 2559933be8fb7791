#pragma once
// Rays through a mesh on the GPU (docs/raycast.md): the mesh core's BVH (geo::TriangleBvh) with
// skip links, walked per ray in a compute pass, the boxes tested
// conservatively in float and the triangles in double precision with the CPU's arithmetic term for
// term, so every answer equals geo::TriangleBvh's: the same face and the same t for the nearest
// hit, the same count of crossings. Any origin and direction.

#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/bvh.h"
#include "gimg/geometry/mesh.h"
#include "gimg/geometry/triangle_queries.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace gimg::passes {

struct GpuRayHit {
    double t = std::numeric_limits<double>::infinity();
    std::uint32_t face = 0xffffffffu;  // 0xffffffff: no hit
    bool found() const { return face != 0xffffffffu; }
};

struct RaycastHandles {
    BufferHandle t, face;  // the new versions of the caller's buffers
};

struct GpuRayCasterOptions {
    // Let the lanes of a subgroup wait for each other before testing triangles (subgroupAll),
    // where the device has subgroup votes in compute shaders. The answers are the same either way.
    bool subgroup_votes = true;
    // Time each call's pass by timestamps (last_gpu_ms). Off by default: lavapipe pays 30-70 us a
    // pass for them.
    bool timestamps = false;
};

class GpuRayCaster {
public:
    // Builds the BVH on the CPU and uploads it. Needs shaderFloat64 (gimg::Error otherwise).
    GpuRayCaster(Context& ctx, const geo::Mesh& mesh, const GpuRayCasterOptions& options = {});
    ~GpuRayCaster();
    GpuRayCaster(const GpuRayCaster&) = delete;
    GpuRayCaster& operator=(const GpuRayCaster&) = delete;

    // TriangleBvh::intersect_nearest for each ray; every ray's front_faces_only must be the same.
    std::vector<GpuRayHit> nearest(std::span<const geo::Ray> rays);
    // The surface's crossings of each ray's [t_min, t_max]: hits within 1e-12 in t count once, so
    // a ray through an edge or a corner of a closed mesh crosses it once.
    std::vector<std::uint32_t> crossings(std::span<const geo::Ray> rays);

    // GPU time of the last call's pass (0 without GpuRayCasterOptions::timestamps, or where the device
    // has none).
    double last_gpu_ms() const { return last_gpu_ms_; }

private:
    friend struct RaycastTree import_raycast_tree(Graph&, GpuRayCaster&);
    friend RaycastHandles add_raycast(Graph&, GpuRayCaster&, BufferHandle, BufferHandle, BufferHandle, std::uint32_t,
                                      std::uint32_t, bool, const std::string&);
    std::vector<std::uint32_t> run(std::span<const geo::Ray> rays, std::uint32_t mode, std::vector<double>* t);
    struct State;
    std::unique_ptr<State> state_;
    double last_gpu_ms_ = 0.0;
};

// The caster's tree imported into a graph, for passes that walk it in their own shaders
// (shaders/raycast/walk.glsl says how: bindings nodes, corners, faces; `scene` is the argument its
// functions take). `votes`: whether to use the shader's subgroup-vote variant. The caster must
// outlive the plan.
struct RaycastTree {
    ImageHandle nodes, corners;
    BufferHandle faces;
    float scene = 0.0f;
    bool votes = false;
};
RaycastTree import_raycast_tree(Graph& graph, GpuRayCaster& caster);

// The cast recorded into a caller's graph: `rays` holds 8 doubles a ray (origin, direction,
// t_min, t_max); `t` (a double a ray) and `face` (a uint a ray: the face, or the crossings) are
// written (t: +inf where nothing is hit). mode 0 nearest, 1 crossings (TriangleBvh::crossings' count,
// however many). The caster must outlive the plan.
RaycastHandles add_raycast(Graph& graph, GpuRayCaster& caster, BufferHandle rays, BufferHandle t, BufferHandle face,
                           std::uint32_t count, std::uint32_t mode, bool front_faces_only,
                           const std::string& name = "raycast");

}  // namespace gimg::passes

#include "embree_peer.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"

#if GIMG_HAS_EMBREE
#include <embree3/rtcore.h>
#endif

namespace gimg::cli {

#if GIMG_HAS_EMBREE

bool embree_available() { return true; }

namespace {
struct Geometry {
    const float* positions;
    const std::uint32_t* triangles;
};

// Keeps hits on triangles whose normal faces the ray's origin, as every gimg method does.
void keep_front_faces(const RTCFilterFunctionNArguments* args) {
    const auto* g = static_cast<const Geometry*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (!args->valid[i]) continue;
        const unsigned f = RTCHitN_primID(args->hit, args->N, i);
        const float* a = g->positions + 3 * g->triangles[3 * f];
        const float* b = g->positions + 3 * g->triangles[3 * f + 1];
        const float* c = g->positions + 3 * g->triangles[3 * f + 2];
        const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0]};
        const float dx = RTCRayN_dir_x(args->ray, args->N, i), dz = RTCRayN_dir_z(args->ray, args->N, i);
        if (!(n[0] * dx + n[2] * dz < 0.0f)) args->valid[i] = 0;
    }
}
}  // namespace

struct EmbreeCylinderCaster::State {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    Geometry geometry{};
    ~State() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

EmbreeCylinderCaster::EmbreeCylinderCaster(const passes::CylinderMesh& mesh) : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.device = rtcNewDevice(nullptr);
    if (!s.device) throw geo::InputError("Embree could not create a device");
    s.scene = rtcNewScene(s.device);
    RTCGeometry g = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Shared buffers: Embree reads gimg's arrays in place (it may read 16 bytes past a vertex, so
    // the vertex array is copied with padding).
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.positions.size() / 3));
    std::copy(mesh.positions.begin(), mesh.positions.end(), vertices);
    auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                        3 * sizeof(std::uint32_t), mesh.face_count()));
    std::copy(mesh.triangles.begin(), mesh.triangles.end(), indices);
    s.geometry = {vertices, indices};
    rtcSetGeometryUserData(g, &s.geometry);
    rtcSetGeometryIntersectFilterFunction(g, keep_front_faces);
    rtcCommitGeometry(g);
    rtcAttachGeometry(s.scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(s.scene);
}

EmbreeCylinderCaster::~EmbreeCylinderCaster() = default;

passes::CylinderImage EmbreeCylinderCaster::project(std::uint32_t width, std::uint32_t height) const {
    passes::CylinderImage image(width, height);
    const auto directions = passes::cylinder_directions(width);
    geo::parallel_for_chunks(height, 1, [&](std::size_t, std::size_t begin, std::size_t end) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (std::size_t v = begin; v < end; ++v) {
            const float y = float(1.0 - (double(v) + 0.5) / double(height));
            for (std::uint32_t u = 0; u < width; ++u) {
                const float c = float(directions[u][0]), s = float(directions[u][1]);
                RTCRayHit rh{};
                rh.ray.org_x = c;  // from the wall, towards the axis and beyond: t in [0, 2]
                rh.ray.org_y = y;
                rh.ray.org_z = s;
                rh.ray.dir_x = -c;
                rh.ray.dir_z = -s;
                rh.ray.tnear = 0.0f;
                rh.ray.tfar = 2.0f;
                rh.ray.mask = ~0u;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(state_->scene, &context, &rh);
                if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
                const std::size_t i = image.index(u, std::uint32_t(v));
                image.covered[i] = 1;
                image.distance[i] = 1.0f - rh.ray.tfar;
            }
        }
    });
    return image;
}

#else

bool embree_available() { return false; }
struct EmbreeCylinderCaster::State {};
EmbreeCylinderCaster::EmbreeCylinderCaster(const passes::CylinderMesh&) {
    throw geo::InputError("this gimg was built without Embree (Debian package libembree-dev)");
}
EmbreeCylinderCaster::~EmbreeCylinderCaster() = default;
passes::CylinderImage EmbreeCylinderCaster::project(std::uint32_t, std::uint32_t) const { return {}; }

#endif

}  // namespace gimg::cli

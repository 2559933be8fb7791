// The CPU reference: one ray per pixel through a BVH. The line of pixel (u, v) is cast from the
// axis point (0, y_v, 0) in the direction opposite to theta_u over t in [-1, 1], keeping front
// faces only; its nearest hit t is the largest d = -t of the definition. Written this way the
// arithmetic is the GPU fragment test's, term for term.
#include "gimg/passes/cylinder.h"

#include "gimg/geometry/bvh.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/passes/raycast.h"

namespace gimg::passes {

geo::Mesh to_cylinder_frame(const CylinderMesh& mesh, const CylinderTransform& m) {
    geo::Mesh out;
    out.positions.reserve(mesh.positions.size() / 3);
    for (std::size_t i = 0; i + 2 < mesh.positions.size(); i += 3) {
        const double x = mesh.positions[i], y = mesh.positions[i + 1], z = mesh.positions[i + 2];
        glm::dvec3 p;
        for (int r = 0; r < 3; ++r)
            p[r] = double(m[4 * r]) * x + double(m[4 * r + 1]) * y + double(m[4 * r + 2]) * z + double(m[4 * r + 3]);
        out.positions.push_back(p);
    }
    out.triangles.reserve(mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        out.triangles.push_back({mesh.triangles[3 * f], mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2]});
    return out;
}

namespace {
geo::Ray pixel_ray(const std::array<double, 2>& direction, std::uint32_t v, std::uint32_t height);
}  // namespace

struct CylinderRaycaster::Bvh {
    geo::TriangleBvh tree;
};

CylinderRaycaster::CylinderRaycaster(const CylinderMesh& mesh, const CylinderTransform& transform)
    : bvh_(std::make_unique<Bvh>()) {
    if (mesh.face_count() > 0) bvh_->tree = geo::TriangleBvh(to_cylinder_frame(mesh, transform));
}

CylinderRaycaster::~CylinderRaycaster() = default;

const geo::TriangleBvh& CylinderRaycaster::bvh() const { return bvh_->tree; }

CylinderImage CylinderRaycaster::project(std::uint32_t width, std::uint32_t height) const {
    CylinderImage image(width, height);
    const geo::TriangleBvh& bvh = bvh_->tree;
    if (bvh.empty()) return image;
    const auto directions = cylinder_directions(width);
    geo::parallel_for_chunks(height, 1, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v) {
            for (std::uint32_t u = 0; u < width; ++u) {
                if (auto hit = bvh.intersect_nearest(pixel_ray(directions[u], std::uint32_t(v), height))) {
                    const std::size_t i = image.index(u, std::uint32_t(v));
                    image.covered[i] = 1;
                    image.distance[i] = float(-hit->t);
                }
            }
        }
    });
    return image;
}

namespace {
// Pixel (u, v)'s ray.
geo::Ray pixel_ray(const std::array<double, 2>& direction, std::uint32_t v, std::uint32_t height) {
    geo::Ray ray;
    ray.origin = {0.0, 1.0 - (double(v) + 0.5) / double(height), 0.0};
    ray.direction = {-direction[0], 0.0, -direction[1]};
    ray.t_min = -1.0;
    ray.t_max = 1.0;
    ray.front_faces_only = true;
    return ray;
}
}  // namespace

CylinderImage cylinder_raycast_gpu(Context& ctx, const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                                   const CylinderTransform& transform) {
    if (mesh.face_count() == 0) return CylinderImage(width, height);
    GpuRayCaster caster(ctx, to_cylinder_frame(mesh, transform));
    return cylinder_raycast_gpu(caster, width, height);
}

CylinderImage cylinder_raycast_gpu(GpuRayCaster& caster, std::uint32_t width, std::uint32_t height) {
    CylinderImage image(width, height);
    const auto directions = cylinder_directions(width);
    std::vector<geo::Ray> rays;
    rays.reserve(std::size_t(width) * height);
    for (std::uint32_t v = 0; v < height; ++v)
        for (std::uint32_t u = 0; u < width; ++u) rays.push_back(pixel_ray(directions[u], v, height));
    const std::vector<GpuRayHit> hits = caster.nearest(rays);
    for (std::size_t i = 0; i < hits.size(); ++i)
        if (hits[i].found()) {
            image.covered[i] = 1;
            image.distance[i] = float(-hits[i].t);
        }
    return image;
}

CylinderImage cylinder_raycast(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                               const CylinderTransform& transform) {
    return CylinderRaycaster(mesh, transform).project(width, height);
}

}  // namespace gimg::passes

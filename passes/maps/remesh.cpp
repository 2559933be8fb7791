// The MAPS pipeline (Fig. 3): base domain, 4-to-1 subdivision, Pi^{-1} at every new point.
#include "gimg/geometry/error.h"
#include "gimg/passes/maps.h"

#include <glm/geometric.hpp>

#include <chrono>
#include <optional>

namespace gimg::passes {

namespace {

// Barycentric coordinates of a base point in base face f (the point must lie in f's closure).
glm::dvec3 in_face(const geo::Mesh& base, const SurfacePoint& p, std::uint32_t f) {
    if (p.face == f) return p.bary;
    const glm::uvec3 from = base.triangles[p.face], to = base.triangles[f];
    glm::dvec3 b(0.0);
    for (int k = 0; k < 3; ++k)
        if (p.bary[k] != 0.0)
            for (int c = 0; c < 3; ++c)
                if (to[c] == from[k]) b[c] = p.bary[k];
    return b;
}

// Relaxes the points inside base faces toward the 3D-length-weighted mean of their neighbours in
// the face's barycentric plane: long 3D edges pull, so the samples spread evenly over the surface.
void relax_remesh(Context* ctx, const geo::Mesh& mesh, MapsRemesh& r, std::uint32_t iterations) {
    SemiRegularMesh& s = r.remesh;
    const std::uint32_t top = s.levels();
    const std::size_t n = s.vertex_count[top];
    std::vector<std::vector<std::uint32_t>> nbr(n);
    for (const glm::uvec3& t : s.faces[top])
        for (int k = 0; k < 3; ++k) {
            nbr[t[k]].push_back(t[(k + 1) % 3]);
        }
    std::vector<std::uint8_t> inside(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 b = s.base_point[i].bary;
        inside[i] = b.x > 0.0 && b.y > 0.0 && b.z > 0.0;
    }
    std::optional<InverseMapBuffers> uploaded;  // the map goes to the device once for all iterations
    if (ctx) uploaded = upload_inverse_map(*ctx, mesh, r.map);
    for (std::uint32_t it = 0; it < iterations; ++it) {
        std::vector<SurfacePoint> next = s.base_point;
        for (std::size_t i = 0; i < n; ++i) {
            if (!inside[i]) continue;
            const std::uint32_t f = s.base_point[i].face;
            glm::dvec3 sum(0.0);
            double weight = 0.0;
            for (std::uint32_t j : nbr[i]) {
                const double w = glm::distance(s.positions[i], s.positions[j]);
                sum += w * in_face(r.domain.base, s.base_point[j], f);
                weight += w;
            }
            if (weight > 0.0) next[i].bary = 0.5 * s.base_point[i].bary + 0.5 * sum / weight;
        }
        s.base_point = next;
        s.positions = ctx ? evaluate_inverse_map_gpu(*ctx, *uploaded, mesh, r.map, s.base_point, &r.fallbacks)
                          : evaluate_inverse_map(mesh, r.map, s.base_point, &r.fallbacks);
    }
}

}  // namespace

MapsRemesh maps_remesh(Context* ctx, const geo::Mesh& mesh, const MapsOptions& options, std::uint32_t levels) {
    using clock = std::chrono::steady_clock;
    auto seconds = [](clock::time_point since) { return std::chrono::duration<double>(clock::now() - since).count(); };
    MapsRemesh r;
    auto t = clock::now();
    r.domain = build_base_domain(mesh, options);
    r.base_seconds = seconds(t);
    t = clock::now();
    r.remesh = subdivide_base(r.domain.base, levels);
    r.subdivide_seconds = seconds(t);
    t = clock::now();
    r.map = build_inverse_map(mesh, r.domain);
    r.locate_seconds = seconds(t);
    t = clock::now();
    r.remesh.positions = ctx ? evaluate_inverse_map_gpu(*ctx, mesh, r.map, r.remesh.base_point, &r.fallbacks)
                             : evaluate_inverse_map(mesh, r.map, r.remesh.base_point, &r.fallbacks);
    r.evaluate_seconds = seconds(t);
    t = clock::now();
    if (options.smoothing) relax_remesh(ctx, mesh, r, options.smoothing);
    r.smoothing_seconds = seconds(t);
    return r;
}

}  // namespace gimg::passes

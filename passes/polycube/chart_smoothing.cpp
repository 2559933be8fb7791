// Step 5 (He et al.; charts after Tarini et al.): the map smoothed on the polycube. Every vertex's
// image moves to the harmonic mean of its neighbours' (positive cotangent weights of the mesh) and
// back onto the polycube's surface: in a face chart the mean stays in the face's plane; at an edge
// or a corner the closest point folds it back onto the faces, as unfolding the chart would. A move
// is kept only when no triangle around the vertex turns its image away from the faces under it, so
// the count of turned triangles never grows.
#include "polycube_parts.h"

#include "gimg/geometry/bvh.h"

#include <algorithm>
#include <cmath>

namespace gimg::passes::polycube {

std::size_t smooth_map(const SlicedMesh& sliced, const geo::Mesh& surface,
                       const std::vector<std::uint8_t>& surface_axis, std::vector<glm::dvec3>& image,
                       std::vector<std::uint8_t>& image_axis, std::uint32_t iterations) {
    if (iterations == 0) return 0;
    const geo::Mesh& mesh = sliced.mesh;
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const std::vector<double> w = positive_cotangent_weights(mesh, adj);
    const geo::TriangleBvh bvh(surface);
    const double diagonal = surface.bounds().diagonal();
    const double min_area2 = std::pow(1e-9 * diagonal * diagonal, 2);

    std::size_t moved = 0;
    std::vector<std::uint32_t> hint(mesh.vertex_count(), geo::kInvalidIndex);
    for (std::uint32_t it = 0; it < iterations; ++it)
        for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
            glm::dvec3 sum(0.0);
            double total = 0.0;
            for (std::uint32_t k = adj.vertex_vertex_offsets[v]; k < adj.vertex_vertex_offsets[v + 1]; ++k) {
                const std::uint32_t u = adj.vertex_vertices[k];
                const double wu = w[adj.find_edge(v, u)];
                sum += wu * image[u];
                total += wu;
            }
            if (!(total > 0.0)) continue;
            const geo::ClosestPointResult c =
                bvh.closest_point(sum / total, std::numeric_limits<double>::infinity(), hint[v]);
            if (!c.found()) continue;
            hint[v] = c.face;
            const auto faces = adj.faces_of_vertex(v);
            // Turned or nearly flat, and turned outright (the count measure_map reports): neither may grow.
            std::size_t turned_before = 0, turned_after = 0, flipped_before = 0, flipped_after = 0;
            for (std::uint32_t f : faces) {
                turned_before += turned(mesh.triangles[f], image, image_axis, min_area2);
                flipped_before += turned(mesh.triangles[f], image, image_axis);
            }
            const glm::dvec3 old = image[v];
            const std::uint8_t old_axis = image_axis[v];
            image[v] = c.point;
            image_axis[v] = surface_axis[c.face];
            for (std::uint32_t f : faces) {
                turned_after += turned(mesh.triangles[f], image, image_axis, min_area2);
                flipped_after += turned(mesh.triangles[f], image, image_axis);
            }
            if (turned_after > turned_before || flipped_after > flipped_before) {
                image[v] = old;
                image_axis[v] = old_axis;
            } else {
                ++moved;
            }
        }
    return moved;
}

}  // namespace gimg::passes::polycube

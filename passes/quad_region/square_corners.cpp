// Corners for trying a region out: a square around the mesh's flattest vertex.
#include "gimg/passes/quad_region.h"

#include "gimg/geometry/curvature.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <numeric>
#include <utility>

namespace gimg::passes {

std::array<std::uint32_t, 4> flattest_square_corners(const QuadRegionCutter& cutter, double side) {
    const geo::Mesh& mesh = cutter.mesh();
    const geo::MeshAdjacency& adj = cutter.adjacency();
    const geo::VertexCurvature k = geo::compute_curvature(mesh, adj);
    const std::vector<glm::dvec3> normals = geo::vertex_normals(mesh);
    const double half = 0.5 * side * mesh.bounds().diagonal();
    std::uint32_t centre = geo::kInvalidIndex;
    double best = 1e300;
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
        if (!k.interior[v]) continue;
        double sum = k.principal_square_sum[v];
        for (std::uint32_t w : adj.neighbors(v)) sum += k.principal_square_sum[w];
        if (sum < best) best = sum, centre = v;
    }
    if (centre == geo::kInvalidIndex) throw geo::InputError("automatic corners: the mesh has no interior vertex");
    const glm::dvec3 n = normals[centre], c = mesh.positions[centre];
    const glm::dvec3 e1 =
        glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 e2 = glm::cross(n, e1);
    std::array<std::uint32_t, 4> corners{};
    const double signs[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 target = c + half * (signs[i][0] * e1 + signs[i][1] * e2);
        double nearest = 1e300;
        for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
            if (glm::dot(normals[v], n) > 0.0 && glm::distance(mesh.positions[v], target) < nearest)
                nearest = glm::distance(mesh.positions[v], target), corners[i] = v;
    }
    // Where the square is wider than the part it sits on (camel's head at 0.25), the sides run round
    // that part and their left is the rest of the mesh: camel's body, which the map squeezes into a
    // point. The square is the smaller side, so a region of more than half the mesh's area is taken
    // the other way round. Corners whose sides cannot be cut are left for the caller's cut to refuse.
    try {
        const QuadRegion region = cutter.cut(corners, false);
        const auto area = [](const geo::Mesh& m) {
            const std::vector<double> a = geo::face_areas(m);
            return std::accumulate(a.begin(), a.end(), 0.0);
        };
        if (area(region.mesh) > 0.5 * area(mesh)) std::swap(corners[1], corners[3]);
    } catch (const geo::InputError&) {}
    return corners;
}

}  // namespace gimg::passes

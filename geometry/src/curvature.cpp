#include "gimg/geometry/curvature.h"

#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/normals.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <numbers>

namespace gimg::geo {

VertexCurvature compute_curvature(const Mesh& mesh, const MeshAdjacency& adjacency) {
    const std::size_t vcount = mesh.vertex_count();
    const std::vector<double> weights = cotangent_weights(mesh, adjacency);
    const std::vector<double> area = vertex_areas(mesh, VertexAreaKind::MixedVoronoi);
    const std::vector<glm::dvec3> normals = vertex_normals(mesh);

    // Angle sums around each vertex.
    std::vector<double> angle_sum(vcount, 0.0);
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k)
            angle_sum[t[k]] +=
                corner_angle(mesh.positions[t[k]], mesh.positions[t[(k + 1) % 3]], mesh.positions[t[(k + 2) % 3]]);

    // sum_j (cot alpha + cot beta)(x_i - x_j) = sum_j 2 w_ij (x_i - x_j), w the edge weight.
    std::vector<glm::dvec3> laplacian(vcount, glm::dvec3(0.0));
    for (std::size_t e = 0; e < adjacency.edge_count(); ++e) {
        const std::uint32_t a = adjacency.edges[2 * e], b = adjacency.edges[2 * e + 1];
        const glm::dvec3 d = 2.0 * weights[e] * (mesh.positions[a] - mesh.positions[b]);
        laplacian[a] += d;
        laplacian[b] -= d;
    }

    VertexCurvature c;
    c.interior = adjacency.interior_vertices();
    c.mean.assign(vcount, 0.0);
    c.gaussian.assign(vcount, 0.0);
    c.principal_square_sum.assign(vcount, 0.0);
    for (std::size_t v = 0; v < vcount; ++v) {
        if (!c.interior[v] || !(area[v] > 0.0)) continue;
        const double magnitude = glm::length(laplacian[v]) / (4.0 * area[v]);
        const double h = glm::dot(laplacian[v], normals[v]) < 0.0 ? -magnitude : magnitude;
        const double k = (2.0 * std::numbers::pi - angle_sum[v]) / area[v];
        c.mean[v] = h;
        c.gaussian[v] = k;
        c.principal_square_sum[v] = std::max(0.0, 4.0 * h * h - 2.0 * k);
    }

    // Non-interior vertices: mean over interior neighbours (values read from interior vertices
    // only, so the order of filling does not matter).
    for (std::size_t v = 0; v < vcount; ++v) {
        if (c.interior[v]) continue;
        double h = 0.0, k = 0.0, s = 0.0;
        std::size_t n = 0;
        for (std::uint32_t j : adjacency.neighbors(v)) {
            if (!c.interior[j]) continue;
            h += c.mean[j];
            k += c.gaussian[j];
            s += c.principal_square_sum[j];
            ++n;
        }
        if (n == 0) continue;
        c.mean[v] = h / double(n);
        c.gaussian[v] = k / double(n);
        c.principal_square_sum[v] = s / double(n);
    }
    return c;
}

}  // namespace gimg::geo

#pragma once
// Corners for a quad region when the user names none (`--corners auto`, and the benchmark's regions).

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/curvature.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/mesh.h"
#include "gimg/geometry/normals.h"

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <cstdint>

namespace gimg::cli {

// --corners auto: a square of side `side` times the diagonal around the flattest interior vertex
// (least k1^2 + k2^2 summed over its ring), corners counter-clockwise seen along its normal.
inline std::array<std::uint32_t, 4> automatic_corners(const geo::Mesh& mesh, double side = 0.2) {
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
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
    if (centre == geo::kInvalidIndex) throw geo::InputError("--corners auto: the mesh has no interior vertex");
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
    return corners;
}

}  // namespace gimg::cli

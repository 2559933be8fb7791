#include "gimg/geometry/cotangent.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace gimg::geo {

double clamped_cotangent(const glm::dvec3& u, const glm::dvec3& v) {
    const double dot = glm::dot(u, v);
    const double sine_scaled = glm::length(glm::cross(u, v));  // |u||v| sin
    if (!(glm::dot(u, u) > 0.0) || !(glm::dot(v, v) > 0.0)) return 0.0;
    if (!(sine_scaled > 0.0)) return dot > 0.0 ? kMaxCotangent : (dot < 0.0 ? -kMaxCotangent : 0.0);
    return std::clamp(dot / sine_scaled, -kMaxCotangent, kMaxCotangent);
}

std::vector<double> cotangent_weights(const Mesh& mesh, const MeshAdjacency& adjacency) {
    std::vector<double> weights(adjacency.edge_count(), 0.0);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        if (t.x == t.y || t.y == t.z || t.z == t.x) continue;
        for (int k = 0; k < 3; ++k) {
            // Edge (corner k, corner k+1) is opposite corner k+2.
            const glm::dvec3& o = mesh.positions[t[(k + 2) % 3]];
            const double cot = clamped_cotangent(mesh.positions[t[k]] - o, mesh.positions[t[(k + 1) % 3]] - o);
            weights[adjacency.face_edges[3 * f + k]] += 0.5 * cot;
        }
    }
    return weights;
}

std::vector<double> vertex_areas(const Mesh& mesh, VertexAreaKind kind) {
    std::vector<double> areas(mesh.vertex_count(), 0.0);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        const glm::dvec3 p[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
        const double area = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
        if (!(area > 0.0)) continue;
        if (kind == VertexAreaKind::Barycentric) {
            for (int k = 0; k < 3; ++k) areas[t[k]] += area / 3.0;
            continue;
        }
        int obtuse = -1;
        for (int k = 0; k < 3; ++k)
            if (glm::dot(p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]) < 0.0) obtuse = k;
        for (int k = 0; k < 3; ++k) {
            if (obtuse >= 0) {
                areas[t[k]] += k == obtuse ? area / 2.0 : area / 4.0;
                continue;
            }
            // Voronoi part of corner P = p[k] with Q = p[k+1], R = p[k+2]:
            // (|PR|^2 cot Q + |PQ|^2 cot R) / 8.
            const glm::dvec3 &P = p[k], &Q = p[(k + 1) % 3], &R = p[(k + 2) % 3];
            const double cot_q = clamped_cotangent(P - Q, R - Q);
            const double cot_r = clamped_cotangent(P - R, Q - R);
            areas[t[k]] += (glm::dot(R - P, R - P) * cot_q + glm::dot(Q - P, Q - P) * cot_r) / 8.0;
        }
    }
    return areas;
}

}  // namespace gimg::geo

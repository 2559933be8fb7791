#include "gimg/geometry/normals.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace gimg::geo {

double corner_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 u = b - a, v = c - a;
    return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
}

std::vector<glm::dvec3> face_normals(const Mesh& mesh) {
    std::vector<glm::dvec3> normals(mesh.face_count(), glm::dvec3(0.0));
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        const glm::dvec3 n =
            glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
        const double len = glm::length(n);
        if (len > 0.0) normals[f] = n / len;
    }
    return normals;
}

std::vector<double> face_areas(const Mesh& mesh) {
    std::vector<double> areas(mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        areas[f] = 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                                mesh.positions[t.z] - mesh.positions[t.x]));
    }
    return areas;
}

std::vector<double> corner_angles(const Mesh& mesh) {
    std::vector<double> angles(3 * mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        for (int k = 0; k < 3; ++k)
            angles[3 * f + k] =
                corner_angle(mesh.positions[t[k]], mesh.positions[t[(k + 1) % 3]], mesh.positions[t[(k + 2) % 3]]);
    }
    return angles;
}

std::vector<glm::dvec3> vertex_normals(const Mesh& mesh) {
    const std::vector<glm::dvec3> fn = face_normals(mesh);
    std::vector<glm::dvec3> normals(mesh.vertex_count(), glm::dvec3(0.0));
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        for (int k = 0; k < 3; ++k)
            normals[t[k]] += fn[f] * corner_angle(mesh.positions[t[k]], mesh.positions[t[(k + 1) % 3]],
                                                  mesh.positions[t[(k + 2) % 3]]);
    }
    for (glm::dvec3& n : normals) {
        const double len = glm::length(n);
        n = len > 0.0 ? n / len : glm::dvec3(0.0);
    }
    return normals;
}

}  // namespace gimg::geo

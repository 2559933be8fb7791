// How good a spherical map is: flips, the paper's conformal energy, angle and area distortion.
#include "gimg/passes/sphere.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gimg::passes {

namespace {

// The three corner angles of triangle (a, b, c), radians.
void corner_angles(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double out[3]) {
    auto angle = [](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
        const glm::dvec3 u = q - p, v = r - p;
        return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
    };
    out[0] = angle(a, b, c);
    out[1] = angle(b, c, a);
    out[2] = angle(c, a, b);
}

}  // namespace

SphereMetrics sphere_metrics(const geo::Mesh& mesh, const std::vector<glm::dvec3>& y) {
    if (y.size() != mesh.vertex_count())
        throw geo::InputError("sphere map has " + std::to_string(y.size()) + " points for " +
                              std::to_string(mesh.vertex_count()) + " vertices");
    SphereMetrics m;
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const std::vector<double> w = geo::cotangent_weights(mesh, adj);
    for (std::size_t e = 0; e < adj.edge_count(); ++e) {
        const glm::dvec3 d = y[adj.edges[2 * e]] - y[adj.edges[2 * e + 1]];
        m.conformal_energy += w[e] * glm::dot(d, d);
    }
    m.conformal_ratio = m.conformal_energy / (8.0 * std::numbers::pi);

    std::vector<double> errors;
    errors.reserve(3 * mesh.face_count());
    std::vector<double> area_mesh(mesh.face_count()), area_sphere(mesh.face_count());
    double total_mesh = 0.0, total_sphere = 0.0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3 t = mesh.triangles[f];
        // det(a, b, c) written a.((b - a) x (c - a)): the plain triple product loses the sign of
        // triangles smaller than about 1e-8, and conformal maps of limbs make such triangles.
        if (!(glm::dot(y[t.x], glm::cross(y[t.y] - y[t.x], y[t.z] - y[t.x])) > 0.0)) ++m.flips;
        double on_mesh[3], on_sphere[3];
        corner_angles(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z], on_mesh);
        corner_angles(y[t.x], y[t.y], y[t.z], on_sphere);
        for (int k = 0; k < 3; ++k) errors.push_back(std::abs(on_sphere[k] - on_mesh[k]) * 180.0 / std::numbers::pi);
        area_mesh[f] = 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                                    mesh.positions[t.z] - mesh.positions[t.x]));
        area_sphere[f] = 0.5 * glm::length(glm::cross(y[t.y] - y[t.x], y[t.z] - y[t.x]));
        total_mesh += area_mesh[f];
        total_sphere += area_sphere[f];
    }
    if (!area_sphere.empty()) m.smallest_area = *std::min_element(area_sphere.begin(), area_sphere.end());
    if (!errors.empty()) {
        double sum = 0.0;
        for (double e : errors) sum += e;
        m.angle_distortion_deg.mean = sum / double(errors.size());
        std::sort(errors.begin(), errors.end());
        m.angle_distortion_deg.p95 = errors[std::min(errors.size() - 1, std::size_t(0.95 * double(errors.size())))];
        m.angle_distortion_deg.max = errors.back();
    }
    // Weighted standard deviation of log(area ratio); triangles collapsed to nothing on the sphere
    // count at the smallest positive ratio seen, so one degenerate face does not make it infinite.
    if (total_mesh > 0.0 && total_sphere > 0.0) {
        double smallest = 1e300;
        for (std::size_t f = 0; f < area_sphere.size(); ++f)
            if (area_sphere[f] > 0.0 && area_mesh[f] > 0.0)
                smallest = std::min(smallest, (area_sphere[f] / total_sphere) / (area_mesh[f] / total_mesh));
        double mean = 0.0, weight = 0.0;
        std::vector<double> logs(area_mesh.size(), 0.0);
        for (std::size_t f = 0; f < area_mesh.size(); ++f) {
            if (area_mesh[f] <= 0.0) continue;
            const double ratio = (area_sphere[f] / total_sphere) / (area_mesh[f] / total_mesh);
            logs[f] = std::log(ratio > 0.0 ? ratio : smallest);
            mean += area_mesh[f] * logs[f];
            weight += area_mesh[f];
        }
        mean /= weight;
        double var = 0.0;
        for (std::size_t f = 0; f < area_mesh.size(); ++f)
            if (area_mesh[f] > 0.0) var += area_mesh[f] * (logs[f] - mean) * (logs[f] - mean);
        m.area_distortion = std::sqrt(var / weight);
    }
    return m;
}

}  // namespace gimg::passes

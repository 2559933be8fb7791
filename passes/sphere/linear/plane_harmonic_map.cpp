// Big-triangle choice and the harmonic map of the rest of the mesh into the plane.
#include "sphere/linear/plane_harmonic_map.h"

#include "gimg/geometry/normals.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace gimg::passes::linear_sphere {

std::uint32_t most_regular_face(const geo::Mesh& mesh) {
    std::uint32_t best = 0;
    double best_irregularity = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3 t = mesh.triangles[f];
        const double e[3] = {glm::length(mesh.positions[t.y] - mesh.positions[t.z]),
                             glm::length(mesh.positions[t.z] - mesh.positions[t.x]),
                             glm::length(mesh.positions[t.x] - mesh.positions[t.y])};
        const double perimeter = e[0] + e[1] + e[2];
        if (!(perimeter > 0.0)) continue;
        double irregularity = 0.0;
        for (double len : e) irregularity += std::abs(len / perimeter - 1.0 / 3.0);
        if (irregularity < best_irregularity) {
            best_irregularity = irregularity;
            best = std::uint32_t(f);
        }
    }
    return best;
}

std::array<std::complex<double>, 3> flat_big_triangle(const geo::Mesh& mesh, std::uint32_t big) {
    const glm::uvec3 t = mesh.triangles[big];
    const glm::dvec3 pa = mesh.positions[t.x], pb = mesh.positions[t.y], pc = mesh.positions[t.z];
    const double angle_a = geo::corner_angle(pa, pb, pc);
    const double ratio = glm::length(pc - pa) / glm::length(pb - pa);
    return {std::complex<double>(0.0, 0.0), std::complex<double>(1.0, 0.0), std::polar(ratio, -angle_a)};
}

DirichletSolution harmonic_map_to_plane(const geo::Mesh& mesh, const geo::MeshAdjacency& adjacency,
                                        const std::vector<double>& edge_weights, std::uint32_t big) {
    const std::size_t n = mesh.vertex_count();
    std::vector<StiffnessEntry> stiffness;
    stiffness.reserve(4 * adjacency.edge_count());
    for (std::size_t e = 0; e < adjacency.edge_count(); ++e) {
        const std::uint32_t a = adjacency.edges[2 * e], b = adjacency.edges[2 * e + 1];
        const double w = edge_weights[e];
        stiffness.push_back({a, a, w});
        stiffness.push_back({b, b, w});
        stiffness.push_back({a, b, -w});
        stiffness.push_back({b, a, -w});
    }

    const glm::uvec3 t = mesh.triangles[big];
    const std::array<std::complex<double>, 3> flat = flat_big_triangle(mesh, big);
    std::vector<std::uint8_t> pinned(n, 0);
    std::vector<std::complex<double>> values(n, {0.0, 0.0});
    pinned[t.x] = pinned[t.y] = pinned[t.z] = 1;
    values[t.x] = flat[0];
    values[t.y] = flat[1];
    values[t.z] = flat[2];

    DirichletSolution plane = solve_dirichlet(n, stiffness, pinned, values);
    if (!plane.ok) return plane;
    std::complex<double> mean(0.0, 0.0);
    for (const auto& z : plane.z) mean += z;
    mean /= double(n);
    for (auto& z : plane.z) z -= mean;
    return plane;
}

std::size_t face_nearest_origin(const geo::Mesh& mesh, const std::vector<std::complex<double>>& w, std::uint32_t big) {
    std::size_t inner = mesh.face_count();
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        if (f == big) continue;
        const glm::uvec3 t = mesh.triangles[f];
        const double d = std::abs(w[t.x]) + std::abs(w[t.y]) + std::abs(w[t.z]);
        if (d < nearest) {
            nearest = d;
            inner = f;
        }
    }
    return inner;
}

double balancing_scale(const geo::Mesh& mesh, const std::vector<std::complex<double>>& w, std::uint32_t big) {
    const std::size_t inner = face_nearest_origin(mesh, w, big);
    if (inner == mesh.face_count()) return 1.0;
    auto mean_edge = [&](std::size_t f, auto chart) {
        const glm::uvec3 t = mesh.triangles[f];
        const std::complex<double> a = chart(w[t.x]), b = chart(w[t.y]), c = chart(w[t.z]);
        return (std::abs(a - b) + std::abs(b - c) + std::abs(c - a)) / 3.0;
    };
    const double north = mean_edge(big, [](std::complex<double> z) { return z; });
    const double south = mean_edge(inner, [](std::complex<double> z) { return 1.0 / z; });
    const double scale = std::sqrt(south / north);
    return std::isfinite(scale) && scale > 0.0 ? scale : 1.0;
}

double dirichlet_energy(const geo::MeshAdjacency& adjacency, const std::vector<double>& edge_weights,
                        const std::vector<std::complex<double>>& z) {
    double energy = 0.0;
    for (std::size_t e = 0; e < adjacency.edge_count(); ++e)
        energy += edge_weights[e] * std::norm(z[adjacency.edges[2 * e]] - z[adjacency.edges[2 * e + 1]]);
    return energy;
}

}  // namespace gimg::passes::linear_sphere

// The factors each iteration applies to the weights: the thesis's density equalisation (6.8-6.10,
// 6.15) and Yoshizawa, Belyaev & Seidel's vertex stretch, plus the measures the iterations report.
#include "parameterize/reweighting.h"

#include "gimg/geometry/curvature.h"
#include "gimg/geometry/normals.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace gimg::passes::detail {

namespace {

double uv_area(const std::vector<glm::dvec2>& uv, const glm::uvec3& t) {
    const glm::dvec2 a = uv[t.y] - uv[t.x], b = uv[t.z] - uv[t.x];
    return 0.5 * (a.x * b.y - a.y * b.x);
}

// Lets `update(i, j, w)` change the weight w of every slot (i, j) of the interior rows and return
// its |sigma - 1|^2 term, normalises each row to sum 1, and returns the mean of the terms (E_sigma).
template <class Update>
double reweigh_rows(const ReweightingInput& in, std::vector<double>& weights, Update&& update) {
    const geo::MeshAdjacency& adj = *in.adjacency;
    double error = 0.0;
    std::size_t slots = 0;
    for (std::size_t i = 0; i < adj.vertex_count(); ++i) {
        if (!in.interior[i]) continue;
        const auto nb = adj.neighbors(i);
        const std::size_t base = adj.vertex_vertex_offsets[i];
        double row = 0.0;
        for (std::size_t k = 0; k < nb.size(); ++k) {
            error += update(i, nb[k], weights[base + k]);
            row += weights[base + k];
            ++slots;
        }
        for (std::size_t k = 0; k < nb.size(); ++k) weights[base + k] /= row;
    }
    return slots ? error / double(slots) : 0.0;
}

}  // namespace

std::vector<double> ring_areas(const geo::MeshAdjacency& adj, const std::vector<double>& face_area) {
    std::vector<double> out(adj.vertex_count(), 0.0);
    for (std::size_t v = 0; v < out.size(); ++v)
        for (std::uint32_t f : adj.faces_of_vertex(v)) out[v] += face_area[f];
    return out;
}

std::vector<double> uv_face_areas(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv) {
    std::vector<double> out(mesh.face_count());
    for (std::size_t f = 0; f < out.size(); ++f) out[f] = uv_area(uv, mesh.triangles[f]);
    return out;
}

std::vector<double> equalised_areas(const ReweightingInput& in, const std::vector<double>& ring_area_2d) {
    std::vector<double> a = ring_area_2d;
    for (std::size_t v = 0; v < a.size(); ++v) {
        if (in.variant != ParameterizeVariant::Density) a[v] /= in.ring_area_3d[v];
        if (in.variant == ParameterizeVariant::Curvature) a[v] /= in.feature[v];
    }
    return a;
}

double area_spread(const std::vector<double>& equalised, const std::vector<std::uint8_t>& interior) {
    double mean = 0.0;
    std::size_t n = 0;
    for (std::size_t v = 0; v < equalised.size(); ++v)
        if (interior[v]) mean += equalised[v], ++n;
    if (n == 0) return 0.0;
    mean /= double(n);
    double sum = 0.0;
    for (std::size_t v = 0; v < equalised.size(); ++v)
        if (interior[v]) {
            const double x = std::log(std::max(equalised[v], 1e-300) / mean);
            sum += x * x;
        }
    return std::sqrt(sum / double(n));
}

double reweigh_by_density(const ReweightingInput& in, const std::vector<double>& ring_area_2d,
                          std::vector<double>& weights) {
    std::vector<double> a = equalised_areas(in, ring_area_2d);
    // (6.9): a boundary vertex's one-ring is cut in half by the boundary, a corner's to a quarter.
    // The ratios of the other variants compare like with like (the 3D ring is cut the same way), so
    // they take the factors only when asked (boundary_factors_on_ratio).
    if (in.variant == ParameterizeVariant::Density || in.boundary_factors_on_ratio)
        for (std::size_t v = 0; v < a.size(); ++v) a[v] *= in.corner[v] ? 4.0 : in.interior[v] ? 1.0 : 2.0;
    return reweigh_rows(in, weights, [&](std::size_t i, std::uint32_t j, double& w) {
        const double sigma = std::sqrt((a[i] + a[j]) / (2.0 * a[i]));  // (6.8)
        w *= sigma;
        return (sigma - 1.0) * (sigma - 1.0);
    });
}

std::vector<double> face_stretch_squared(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv,
                                         const std::vector<double>& face_area_3d) {
    // The 2D map scaled to the 3D surface's area, so an isometry has stretch 1.
    double area_2d = 0.0, area_3d = 0.0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        area_2d += std::abs(uv_area(uv, mesh.triangles[f])), area_3d += face_area_3d[f];
    const double scale = std::sqrt(area_2d / area_3d);  // divides uv
    std::vector<double> out(mesh.face_count());
    for (std::size_t f = 0; f < out.size(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        const glm::dvec2 p1 = uv[t.x] / scale, p2 = uv[t.y] / scale, p3 = uv[t.z] / scale;
        const double area = 0.5 * ((p2.x - p1.x) * (p3.y - p1.y) - (p3.x - p1.x) * (p2.y - p1.y));
        // A triangle flattened onto one side of the square has no stretch to speak of (NaN: left
        // out of the sums); a flipped one has infinite stretch.
        if (!(area > 0.0)) {
            out[f] = area == 0.0 ? std::numeric_limits<double>::quiet_NaN() : std::numeric_limits<double>::infinity();
            continue;
        }
        const glm::dvec3 &q1 = mesh.positions[t.x], &q2 = mesh.positions[t.y], &q3 = mesh.positions[t.z];
        // Sander et al. 2001: the partial derivatives of the surface along s and t.
        const glm::dvec3 ss = (q1 * (p2.y - p3.y) + q2 * (p3.y - p1.y) + q3 * (p1.y - p2.y)) / (2.0 * area);
        const glm::dvec3 st = (q1 * (p3.x - p2.x) + q2 * (p1.x - p3.x) + q3 * (p2.x - p1.x)) / (2.0 * area);
        out[f] = 0.5 * (glm::dot(ss, ss) + glm::dot(st, st));
    }
    return out;
}

double l2_stretch(const std::vector<double>& stretch_squared, const std::vector<double>& face_area_3d) {
    double sum = 0.0, area = 0.0;
    for (std::size_t f = 0; f < stretch_squared.size(); ++f)
        if (!std::isnan(stretch_squared[f])) sum += face_area_3d[f] * stretch_squared[f], area += face_area_3d[f];
    return std::sqrt(sum / area);
}

std::vector<double> vertex_stretch(const geo::MeshAdjacency& adj, const std::vector<double>& stretch_squared,
                                   const std::vector<double>& face_area_3d) {
    std::vector<double> vertex(adj.vertex_count(), 0.0);
    for (std::size_t v = 0; v < vertex.size(); ++v) {
        double sum = 0.0, area = 0.0;
        for (std::uint32_t f : adj.faces_of_vertex(v))
            if (!std::isnan(stretch_squared[f])) sum += face_area_3d[f] * stretch_squared[f], area += face_area_3d[f];
        vertex[v] = area > 0.0 ? std::sqrt(sum / area) : 1.0;
    }
    return vertex;
}

double reweigh_by_stretch(const ReweightingInput& in, const std::vector<double>& stretch_squared,
                          std::vector<double>& weights) {
    const std::vector<double> vertex = vertex_stretch(*in.adjacency, stretch_squared, in.face_area_3d);
    return reweigh_rows(in, weights, [&](std::size_t i, std::uint32_t j, double& w) {
        w /= vertex[j];
        const double factor = vertex[i] / vertex[j];
        return (factor - 1.0) * (factor - 1.0);
    });
}

}  // namespace gimg::passes::detail

namespace gimg::passes {

std::vector<double> curvature_feature(const geo::Mesh& mesh, const geo::MeshAdjacency& adj, double root) {
    // The filter's sigma_L = 0.1 is a length: on the mesh scaled to a unit bounding-box diagonal.
    geo::Mesh unit = mesh;
    const double diagonal = mesh.bounds().diagonal();
    for (auto& p : unit.positions) p /= diagonal;
    const geo::VertexCurvature k = geo::compute_curvature(unit, adj);
    std::vector<double> c(mesh.vertex_count());
    // (6.13); below k ~ 1e-5 (a radius of 1e5 diagonals) the surface is flat: rounding, not shape.
    for (std::size_t v = 0; v < c.size(); ++v)
        c[v] = k.principal_square_sum[v] < 1e-10 ? 0.0 : std::pow(k.principal_square_sum[v], 1.0 / root);
    // (6.14) with the sign that smooths: C_i += 1/n_i sum_j L(|x_i - x_j|) D(C_i - C_j) (C_j - C_i),
    // twice, each pass from the previous pass's values.
    constexpr double kSigmaL = 0.1, kSigmaD = 2.0;
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<double> next = c;
        for (std::size_t i = 0; i < c.size(); ++i) {
            const auto nb = adj.neighbors(i);
            if (nb.empty()) continue;
            double sum = 0.0;
            for (std::uint32_t j : nb) {
                const double dx = glm::distance(unit.positions[i], unit.positions[j]), dc = c[i] - c[j];
                sum += std::exp(-dx * dx / (2 * kSigmaL * kSigmaL)) * std::exp(-dc * dc / (2 * kSigmaD * kSigmaD)) *
                       (c[j] - c[i]);
            }
            next[i] = c[i] + sum / double(nb.size());
        }
        c = std::move(next);
    }
    // C divides the area: a flat region (C = 0) would take every sample. The text is silent; we
    // floor C at a twentieth of its mean, and a flat mesh has C = 1 everywhere.
    const double mean = std::accumulate(c.begin(), c.end(), 0.0) / double(c.size());
    for (double& x : c) x = mean > 0.0 ? std::max(x, 0.05 * mean) : 1.0;
    return c;
}

}  // namespace gimg::passes

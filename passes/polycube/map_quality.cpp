// How good the polycube map is (docs/polycube.md, Measures): chords turned in mapped.ply, and the
// Evocube area and angle distortion (area-weighted means and medians).
#include "polycube_parts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace gimg::passes::polycube {

namespace {

// Singular values of the linear map from triangle a to triangle b (each in its own plane).
std::pair<double, double> singular_values(const glm::dvec3 a[3], const glm::dvec3 b[3]) {
    const glm::dvec3 e1 = a[1] - a[0], e2 = a[2] - a[0], f1 = b[1] - b[0], f2 = b[2] - b[0];
    const double g11 = glm::dot(e1, e1), g12 = glm::dot(e1, e2), g22 = glm::dot(e2, e2);
    const double h11 = glm::dot(f1, f1), h12 = glm::dot(f1, f2), h22 = glm::dot(f2, f2);
    const double det_g = g11 * g22 - g12 * g12;
    if (!(det_g > 0.0)) return {0.0, 0.0};
    // G^-1 H: its eigenvalues are the squared singular values.
    const double m11 = (g22 * h11 - g12 * h12) / det_g, m12 = (g22 * h12 - g12 * h22) / det_g,
                 m21 = (g11 * h12 - g12 * h11) / det_g, m22 = (g11 * h22 - g12 * h12) / det_g;
    const double tr = m11 + m22, det = std::max(m11 * m22 - m12 * m21, 0.0);
    const double disc = std::sqrt(std::max(tr * tr / 4.0 - det, 0.0));
    return {std::sqrt(std::max(tr / 2.0 + disc, 0.0)), std::sqrt(std::max(tr / 2.0 - disc, 0.0))};
}

const glm::dvec3 kAxis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

}  // namespace

std::pair<double, double> triangle_distortion(const glm::dvec3 a[3], const glm::dvec3 b[3]) {
    const auto [s1, s2] = singular_values(a, b);
    if (!(s2 > 1e-12)) return {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    return {0.5 * (s1 * s2 + 1.0 / (s1 * s2)), 0.5 * (s1 / s2 + s2 / s1)};
}

double image_scale(const SlicedMesh& sliced, const std::vector<glm::dvec3>& rest, const std::vector<glm::dvec3>& image,
                   std::size_t original_faces) {
    double area = 0.0, image_area = 0.0;
    for (std::size_t f = 0; f < sliced.mesh.face_count(); ++f) {
        if (sliced.source_face[f] >= original_faces) continue;
        const glm::uvec3& t = sliced.mesh.triangles[f];
        area += glm::length(glm::cross(rest[t[1]] - rest[t[0]], rest[t[2]] - rest[t[0]]));
        image_area += glm::length(glm::cross(image[t[1]] - image[t[0]], image[t[2]] - image[t[0]]));
    }
    return image_area > 0.0 ? std::sqrt(area / image_area) : 1.0;
}

bool turned(const glm::uvec3& t, const std::vector<glm::dvec3>& image, const std::vector<std::uint8_t>& axis,
            double min_area2) {
    const glm::dvec3 n = glm::cross(image[t[1]] - image[t[0]], image[t[2]] - image[t[0]]);
    const glm::dvec3 expected = kAxis[axis[t[0]]] + kAxis[axis[t[1]]] + kAxis[axis[t[2]]];
    return !(glm::dot(n, expected) > 0.0 && glm::dot(n, n) > min_area2);
}

void measure_map(const SlicedMesh& sliced, const PolycubeMap& m, std::size_t original_faces,
                 PolycubeStatistics& stats) {
    // Flips and distortion over the real triangles of the sliced mesh.
    std::vector<std::size_t> real;
    for (std::size_t f = 0; f < sliced.mesh.face_count(); ++f) {
        if (sliced.source_face[f] >= original_faces) continue;
        if (turned(sliced.mesh.triangles[f], m.image, m.image_axis)) ++stats.turned_chords;
        real.push_back(f);
    }
    const double scale = image_scale(sliced, sliced.mesh.positions, m.image, original_faces);
    double wsum = 0.0;
    std::vector<std::tuple<double, double, double>> per_triangle;  // area, angle, weight
    for (std::size_t f : real) {
        const auto& t = sliced.mesh.triangles[f];
        const glm::dvec3 a[3] = {sliced.mesh.positions[t[0]], sliced.mesh.positions[t[1]], sliced.mesh.positions[t[2]]};
        const glm::dvec3 b[3] = {scale * m.image[t[0]], scale * m.image[t[1]], scale * m.image[t[2]]};
        const auto [area, angle] = triangle_distortion(a, b);
        const double w = 0.5 * glm::length(glm::cross(a[1] - a[0], a[2] - a[0]));
        if (std::isinf(area) || w <= 0.0) continue;
        stats.area_distortion += w * area;
        stats.angle_distortion += w * angle;
        per_triangle.emplace_back(area, angle, w);
        wsum += w;
    }
    if (wsum > 0) stats.area_distortion /= wsum, stats.angle_distortion /= wsum;
    // Area-weighted medians: the means above follow a few collapsed images.
    for (int which = 0; which < 2; ++which) {
        std::sort(per_triangle.begin(), per_triangle.end(), [&](const auto& x, const auto& y) {
            return which ? std::get<1>(x) < std::get<1>(y) : std::get<0>(x) < std::get<0>(y);
        });
        double run = 0.0;
        for (const auto& x : per_triangle) {
            run += std::get<2>(x);
            if (run >= 0.5 * wsum) {
                (which ? stats.angle_distortion_median : stats.area_distortion_median) =
                    which ? std::get<1>(x) : std::get<0>(x);
                break;
            }
        }
    }
}

}  // namespace gimg::passes::polycube

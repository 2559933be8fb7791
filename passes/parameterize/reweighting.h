#pragma once
// The reweighting steps of parameterize_square (docs/gim.md): each multiplies the weights of the
// interior rows by its factors, normalises the rows and returns its E_sigma.

#include "gimg/passes/parameterize.h"

#include <vector>

namespace gimg::passes::detail {

struct ReweightingInput {
    ParameterizeVariant variant = ParameterizeVariant::Density;
    const geo::MeshAdjacency* adjacency = nullptr;
    std::vector<std::uint8_t> interior;  // 1: a free row
    std::vector<std::uint8_t> corner;    // 1: one of the square's corners
    std::vector<double> face_area_3d;
    std::vector<double> ring_area_3d;
    std::vector<double> feature;  // curvature variant: C per vertex
    bool boundary_factors_on_ratio = false;
};

std::vector<double> uv_face_areas(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv);
// Per vertex, the sum of its faces' areas.
std::vector<double> ring_areas(const geo::MeshAdjacency& adj, const std::vector<double>& face_area);

// What the variant equalises: A (density), A / A_3D (uniform3d, and the measure for the others),
// A / A_3D / C (curvature).
std::vector<double> equalised_areas(const ReweightingInput& in, const std::vector<double>& ring_area_2d);
// Standard deviation of log(a_i / mean a) over interior vertices.
double area_spread(const std::vector<double>& equalised, const std::vector<std::uint8_t>& interior);

// w_ij *= sqrt((A'_i + A'_j) / (2 A'_i)) (6.8), with the corner x4 and boundary x2 factors (6.9).
double reweigh_by_density(const ReweightingInput& in, const std::vector<double>& ring_area_2d,
                          std::vector<double>& weights);

// Sander's squared L2 stretch per face (infinite where the parameter triangle is flipped or flat),
// the map scaled to the surface's area.
std::vector<double> face_stretch_squared(const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv,
                                         const std::vector<double>& face_area_3d);
double l2_stretch(const std::vector<double>& stretch_squared, const std::vector<double>& face_area_3d);
// Per vertex, its L2 stretch: the 3D-area-weighted root mean square of its faces' (1 where none counts).
std::vector<double> vertex_stretch(const geo::MeshAdjacency& adj, const std::vector<double>& stretch_squared,
                                   const std::vector<double>& face_area_3d);
// Yoshizawa et al.: w_ij /= sigma(v_j), sigma(v) the vertex's L2 stretch. Returns the mean of
// |sigma(v_i) / sigma(v_j) - 1|^2 over the directed edges of interior rows.
double reweigh_by_stretch(const ReweightingInput& in, const std::vector<double>& stretch_squared,
                          std::vector<double>& weights);

}  // namespace gimg::passes::detail

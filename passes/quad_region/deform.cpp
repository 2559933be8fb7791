// Deformations through the region's map (sec. 5): P'_i = P_i + F(u_i, v_i), F a lattice of offsets
// on clamped cubic B-splines (the outer layers fixed at zero) or a height along the normal.
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/passes/quad_region.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace gimg::passes {

namespace {

// The N clamped cubic B-spline basis values at x in [0, 1]: knots 0,0,0,0, 1/(N-3), ..., 1,1,1,1
// (Cox-de Boor).
std::vector<double> cubic_basis(std::uint32_t n, double x) {
    const std::uint32_t spans = n - 3;
    std::vector<double> knots;
    for (int i = 0; i < 3; ++i) knots.push_back(0.0);
    for (std::uint32_t i = 0; i <= spans; ++i) knots.push_back(double(i) / spans);
    for (int i = 0; i < 3; ++i) knots.push_back(1.0);
    x = std::clamp(x, 0.0, 1.0);
    // Degree 0: the one span holding x (the last span holds x = 1).
    std::vector<double> b(knots.size() - 1, 0.0);
    for (std::size_t i = 0; i + 1 < knots.size(); ++i)
        if (knots[i] < knots[i + 1] && ((x >= knots[i] && x < knots[i + 1]) || (x == 1.0 && knots[i + 1] == 1.0)))
            b[i] = 1.0;
    for (int p = 1; p <= 3; ++p)
        for (std::size_t i = 0; i + p + 1 < knots.size(); ++i) {
            const double l = knots[i + p] > knots[i] ? (x - knots[i]) / (knots[i + p] - knots[i]) * b[i] : 0.0;
            const double r = knots[i + p + 1] > knots[i + 1]
                                 ? (knots[i + p + 1] - x) / (knots[i + p + 1] - knots[i + 1]) * b[i + 1]
                                 : 0.0;
            b[i] = l + r;
        }
    b.resize(n);
    return b;
}

void check_map(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv) {
    if (uv.size() != region.mesh.vertex_count())
        throw geo::InputError("the map has " + std::to_string(uv.size()) + " parameters for a region of " +
                              std::to_string(region.mesh.vertex_count()) + " vertices");
    for (std::uint32_t o : region.original)
        if (o != kInsertedNode && o >= mesh.vertex_count())
            throw geo::InputError("the region was cut from another mesh");
}

}  // namespace

glm::dvec3 OffsetLattice::evaluate(glm::dvec2 uv) const {
    if (columns < 4 || rows < 4) throw geo::InputError("an offset lattice needs at least 4 x 4 control points");
    if (offsets.size() != std::size_t(columns) * rows)
        throw geo::InputError("the lattice has " + std::to_string(offsets.size()) + " offsets for " +
                              std::to_string(columns) + " x " + std::to_string(rows) + " control points");
    const std::vector<double> bu = cubic_basis(columns, uv.x), bv = cubic_basis(rows, uv.y);
    auto free = [&](std::uint32_t i, std::uint32_t n) {
        return int(i) > fixed_layers && int(i) + 1 + fixed_layers < int(n);
    };
    glm::dvec3 f(0.0);
    for (std::uint32_t q = 0; q < rows; ++q)
        for (std::uint32_t p = 0; p < columns; ++p)
            if (free(p, columns) && free(q, rows)) f += offsets[std::size_t(q) * columns + p] * (bu[p] * bv[q]);
    return f;
}

double PastedFeature::evaluate(glm::dvec2 uv) const {
    if (heights.empty()) {
        auto b = [](double x) { return std::pow(4.0 * x * (1.0 - x), 3.0); };
        return scale * b(std::clamp(uv.x, 0.0, 1.0)) * b(std::clamp(uv.y, 0.0, 1.0));
    }
    if (heights.size() != std::size_t(width) * height || width < 2 || height < 2)
        throw geo::InputError("a height map needs at least 2 x 2 values");
    const double x = std::clamp(uv.x, 0.0, 1.0) * (width - 1), y = (1.0 - std::clamp(uv.y, 0.0, 1.0)) * (height - 1);
    const std::uint32_t x0 = std::min(std::uint32_t(x), width - 2), y0 = std::min(std::uint32_t(y), height - 2);
    const double fx = x - x0, fy = y - y0;
    auto at = [&](std::uint32_t i, std::uint32_t j) { return double(heights[std::size_t(j) * width + i]); };
    return scale * ((at(x0, y0) * (1 - fx) + at(x0 + 1, y0) * fx) * (1 - fy) +
                    (at(x0, y0 + 1) * (1 - fx) + at(x0 + 1, y0 + 1) * fx) * fy);
}

geo::Mesh deform_by_lattice(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                            const OffsetLattice& lattice) {
    check_map(mesh, region, uv);
    geo::Mesh out = mesh;
    for (std::size_t i = 0; i < uv.size(); ++i)
        if (region.original[i] != kInsertedNode) out.positions[region.original[i]] += lattice.evaluate(uv[i]);
    return out;
}

geo::Mesh paste_feature(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                        const PastedFeature& feature) {
    check_map(mesh, region, uv);
    // The unweighted mean of the unit normals of the faces at a vertex, of the undeformed mesh.
    const std::vector<glm::dvec3> face_n = geo::face_normals(mesh);
    std::vector<glm::dvec3> normal(mesh.vertex_count(), glm::dvec3(0.0));
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (int k = 0; k < 3; ++k) normal[mesh.triangles[f][k]] += face_n[f];
    const double diagonal = mesh.bounds().diagonal();
    geo::Mesh out = mesh;
    for (std::size_t i = 0; i < uv.size(); ++i) {
        const std::uint32_t o = region.original[i];
        if (o == kInsertedNode || glm::length(normal[o]) == 0.0) continue;
        out.positions[o] += glm::normalize(normal[o]) * (feature.evaluate(uv[i]) * diagonal);
    }
    return out;
}

}  // namespace gimg::passes

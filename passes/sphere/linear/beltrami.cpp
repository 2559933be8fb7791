// Beltrami coefficient of a planar layout against the mesh, and the linear Beltrami solver.
#include "sphere/linear/beltrami.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace gimg::passes::linear_sphere {

namespace {

using Complex = std::complex<double>;

double cross2(Complex a, Complex b) { return a.real() * b.imag() - a.imag() * b.real(); }

}  // namespace

std::vector<Complex> beltrami_coefficients(const geo::Mesh& mesh, const std::vector<Complex>& plane,
                                           const std::vector<std::uint8_t>& faces) {
    std::vector<Complex> mu(mesh.face_count(), Complex(0.0, 0.0));
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        if (!faces[f]) continue;
        const glm::uvec3 t = mesh.triangles[f];
        const Complex e1 = plane[t.y] - plane[t.x], e2 = plane[t.z] - plane[t.x];
        const glm::dvec3 x1 = mesh.positions[t.y] - mesh.positions[t.x];
        const glm::dvec3 x2 = mesh.positions[t.z] - mesh.positions[t.x];
        // The affine map's partial derivatives d/du, d/dv, each times the planar triangle's doubled
        // signed area: mu is a ratio of quadratic forms in them, so the common factor cancels
        // (and its sign with it, which is why the metric cannot tell orientation).
        const glm::dvec3 du = x1 * e2.imag() - x2 * e1.imag();
        const glm::dvec3 dv = x2 * e1.real() - x1 * e2.real();
        const double e = glm::dot(du, du), g = glm::dot(dv, dv), fm = glm::dot(du, dv);
        if (cross2(e1, e2) == 0.0) {
            mu[f] = Complex(std::numeric_limits<double>::quiet_NaN(), 0.0);
            continue;
        }
        // sqrt(EG - F^2) as |du x dv|: no cancellation when the metric is nearly degenerate.
        mu[f] = Complex(e - g, 2.0 * fm) / (e + g + 2.0 * glm::length(glm::cross(du, dv)));
    }
    return mu;
}

DirichletSolution linear_beltrami_solve(const geo::Mesh& mesh, const std::vector<Complex>& plane,
                                        const std::vector<Complex>& mu, const std::vector<std::uint8_t>& pinned,
                                        const std::vector<Complex>& pinned_values) {
    std::vector<StiffnessEntry> stiffness;
    stiffness.reserve(9 * mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3 t = mesh.triangles[f];
        const std::uint32_t v[3] = {t.x, t.y, t.z};
        if (pinned[v[0]] && pinned[v[1]] && pinned[v[2]]) continue;  // only pinned rows: not needed
        const Complex m = mu[f];
        const double one_minus = 1.0 - std::norm(m);
        const double area2 = std::abs(cross2(plane[v[1]] - plane[v[0]], plane[v[2]] - plane[v[0]]));
        std::string why;
        if (!std::isfinite(area2))
            why = "has a vertex at infinity in the plane (at the projection pole)";
        else if (!(area2 > 0.0))
            why = "has collapsed to a point or a line in the plane (squeezed below double precision)";
        else if (!std::isfinite(m.real()) || !std::isfinite(m.imag()))
            why = "has no finite Beltrami coefficient";
        else if (!(one_minus > 0.0))
            why = "has |mu| = " + std::to_string(std::abs(m)) + " (a solvable equation needs < 1)";
        if (!why.empty()) {
            DirichletSolution failed;
            failed.why = "face " + std::to_string(f) + " " + why;
            return failed;
        }
        const double a11 = std::norm(1.0 - m) / one_minus;
        const double a12 = -2.0 * m.imag() / one_minus;
        const double a22 = std::norm(1.0 + m) / one_minus;
        // Gradient of the hat function of corner k is the opposite edge turned by 90 degrees over
        // the doubled signed area; the stiffness integrates grad_i . A grad_j over the triangle,
        // |T| / (2|T|)^2 = 1 / (2 * area2). The turn is the same for all corners, so using the edge
        // turned either way gives the same products.
        Complex grad[3];
        for (int k = 0; k < 3; ++k) {
            const Complex edge = plane[v[(k + 2) % 3]] - plane[v[(k + 1) % 3]];
            grad[k] = Complex(-edge.imag(), edge.real());
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const double gi_a_gj = a11 * grad[i].real() * grad[j].real() +
                                       a12 * (grad[i].real() * grad[j].imag() + grad[i].imag() * grad[j].real()) +
                                       a22 * grad[i].imag() * grad[j].imag();
                stiffness.push_back({v[i], v[j], gi_a_gj / (2.0 * area2)});
            }
    }
    return solve_dirichlet(mesh.vertex_count(), stiffness, pinned, pinned_values);
}

}  // namespace gimg::passes::linear_sphere

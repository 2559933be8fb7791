// White-box checks of the linear Beltrami solver inside `linear` (passes/sphere/linear), against
// answers it cannot match by accident: Beltrami coefficients of affine layouts, known by hand,
// and the identity that makes the south-pole step work. When mu is the coefficient of a planar
// layout against the mesh's own metric, the solver's linear-element matrix is each triangle's
// Dirichlet energy measured in that metric, that is, the mesh's cotangent Laplacian: the solve
// must then equal a cotangent harmonic map with the same pinned vertices, however the layout
// distorts the triangles.
#include "sphere/linear/beltrami.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <complex>

using namespace gimg;
using namespace gimg::passes::linear_sphere;
using Complex = std::complex<double>;

namespace {

std::vector<Complex> layout(const geo::Mesh& flat, Complex (*map)(double x, double y)) {
    std::vector<Complex> q;
    for (const auto& p : flat.positions) q.push_back(map(p.x, p.y));
    return q;
}

}  // namespace

TEST(SphereLinearBeltrami, CoefficientsOfAffineLayoutsAreKnown) {
    const geo::Mesh grid = geo::make_grid(4, 3);  // flat, z = 0
    const std::vector<std::uint8_t> all(grid.face_count(), 1);
    struct Case {
        const char* what;
        Complex (*map)(double, double);
        Complex mu;  // of the map layout -> mesh, the inverse of `map`
    };
    const Case cases[] = {
        {"identity", [](double x, double y) { return Complex(x, y); }, {0.0, 0.0}},
        {"rotation and scale", [](double x, double y) { return Complex(0.3, 1.1) * Complex(x, y); }, {0.0, 0.0}},
        // The metric cannot see a mirror: still conformal.
        {"mirror", [](double x, double y) { return Complex(x, -y); }, {0.0, 0.0}},
        // Layout stretched 2x along x: the mesh is the layout squeezed to (u / 2, v), mu = (1/2 - 1) / (1/2 + 1).
        {"stretch", [](double x, double y) { return Complex(2.0 * x, y); }, {-1.0 / 3.0, 0.0}},
    };
    for (const Case& c : cases) {
        const std::vector<Complex> mu = beltrami_coefficients(grid, layout(grid, c.map), all);
        for (const Complex& m : mu) EXPECT_NEAR(std::abs(m - c.mu), 0.0, 1e-12) << c.what;
    }
}

TEST(SphereLinearBeltrami, SolveWithTheMeshMetricIsTheCotangentHarmonicMap) {
    geo::Mesh e = geo::make_icosphere(1.0, 3);
    for (auto& p : e.positions) p *= glm::dvec3(1.0, 2.0, 0.7);  // triaxial: no symmetry to hide behind
    // A distorted layout: the radial projection seen from the north pole, pinned far out.
    std::vector<Complex> q;
    std::vector<std::uint8_t> pinned;
    for (const auto& p : e.positions) {
        const glm::dvec3 u = glm::normalize(p);
        q.push_back(Complex(u.x, u.y) / (1.0 + u.z));
        pinned.push_back(!(std::abs(q.back()) <= 1.5));  // the south pole itself is 0 / 0 = NaN
    }
    std::vector<std::uint8_t> needed;  // faces touching a free vertex; the south pole's is at infinity
    for (const auto& t : e.triangles) needed.push_back(!(pinned[t.x] && pinned[t.y] && pinned[t.z]));
    const DirichletSolution lbs = linear_beltrami_solve(e, q, beltrami_coefficients(e, q, needed), pinned, q);

    const geo::MeshAdjacency adj = geo::build_adjacency(e);
    const std::vector<double> cot = geo::cotangent_weights(e, adj);
    std::vector<StiffnessEntry> laplacian;
    for (std::size_t k = 0; k < adj.edge_count(); ++k) {
        const std::uint32_t a = adj.edges[2 * k], b = adj.edges[2 * k + 1];
        laplacian.insert(laplacian.end(), {{a, a, cot[k]}, {b, b, cot[k]}, {a, b, -cot[k]}, {b, a, -cot[k]}});
    }
    const DirichletSolution harmonic = solve_dirichlet(e.vertex_count(), laplacian, pinned, q);

    ASSERT_TRUE(lbs.ok) << lbs.why;
    ASSERT_TRUE(harmonic.ok) << harmonic.why;
    double moved = 0.0, differ = 0.0;
    for (std::size_t v = 0; v < q.size(); ++v) {
        moved = std::max(moved, std::abs(lbs.z[v] - q[v]));
        differ = std::max(differ, std::abs(lbs.z[v] - harmonic.z[v]));
    }
    EXPECT_GT(moved, 0.01);  // the layout was not already the answer
    EXPECT_LT(differ, 1e-10);
}

TEST(SphereLinearBeltrami, ACollapsedLayoutIsReportedNotSolved) {
    const geo::Mesh grid = geo::make_grid(2, 2);
    std::vector<Complex> q = layout(grid, [](double x, double y) { return Complex(x, y); });
    q[4] = q[0];  // the centre vertex on a corner: its faces collapse or fold
    std::vector<std::uint8_t> pinned(grid.vertex_count(), 1);
    pinned[4] = 0;
    const std::vector<std::uint8_t> all(grid.face_count(), 1);
    const DirichletSolution s = linear_beltrami_solve(grid, q, beltrami_coefficients(grid, q, all), pinned, q);
    EXPECT_FALSE(s.ok);
    EXPECT_NE(s.why.find("collapsed"), std::string::npos) << s.why;
}

// The Dirichlet problem of the planar polish, built from a relaxed sphere map.
#include "sphere/harmonic/chart_problem.h"

#include "sphere/linear/stereographic.h"
#include "sphere/sphere_steps.h"

#include "gimg/geometry/parallel_for.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gimg::passes::detail {

glm::dvec3 largest_triangle_pole(const RelaxationMesh& level, const std::vector<glm::dvec3>& y) {
    double best = -1.0;
    glm::dvec3 pole(0.0, 0.0, 1.0);
    for (std::uint32_t v = 0; v < level.vertex_count(); ++v) {
        const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
        for (std::uint32_t k = 0; k < degree; ++k) {
            const std::uint32_t a = level.ring[begin + k], b = level.ring[begin + (k + 1) % degree];
            if (a < v || b < v) continue;  // each triangle once, from its smallest vertex
            const double area = glm::length(glm::cross(y[a] - y[v], y[b] - y[v]));
            if (area > best) {
                best = area;
                pole = glm::normalize(y[v] + y[a] + y[b]);
            }
        }
    }
    return pole;
}

namespace {

glm::dvec2 chart_point(const glm::dmat3& frame, const glm::dvec3& p) {
    const linear_sphere::Complex w = linear_sphere::south_chart_from_sphere(glm::transpose(frame) * p);
    return {w.real(), w.imag()};
}

}  // namespace

ChartProblem make_dirichlet_problem(const RelaxationMesh& level, const std::vector<std::uint8_t>& pinned,
                                    const std::vector<glm::dvec2>& chart) {
    const std::size_t n = level.vertex_count();
    ChartProblem problem;
    // Room for every row and spoke up front (growing the arrays took a third of the time).
    problem.free_vertices.reserve(n);
    problem.row_offsets.reserve(n + 1);
    problem.columns.reserve(level.ring.size());
    problem.values.reserve(level.ring.size());
    problem.diagonal.reserve(n);
    problem.rhs.reserve(n);
    problem.start.reserve(n);
    std::vector<std::uint32_t> row_of(n, 0);
    for (std::uint32_t v = 0; v < n; ++v) {
        if (pinned[v]) continue;
        row_of[v] = std::uint32_t(problem.free_vertices.size());
        problem.free_vertices.push_back(v);
    }
    problem.row_offsets.push_back(0);
    for (std::uint32_t v : problem.free_vertices) {
        double diagonal = 0.0;
        glm::dvec2 rhs(0.0);
        for (std::uint32_t k = level.ring_offsets[v]; k < level.ring_offsets[v + 1]; ++k) {
            const std::uint32_t u = level.ring[k];
            const double w = level.ring_weights[k];
            diagonal += w;
            if (pinned[u]) {
                rhs += w * chart[u];
            } else {
                problem.columns.push_back(row_of[u]);
                problem.values.push_back(-w);
            }
        }
        problem.row_offsets.push_back(std::uint32_t(problem.columns.size()));
        problem.diagonal.push_back(diagonal);
        problem.rhs.push_back(rhs);
        problem.start.push_back(chart[v]);
    }
    return problem;
}

ChartProblem make_chart_problem(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, const glm::dvec3& pole,
                                double cap_fraction) {
    const std::size_t n = level.vertex_count();
    const glm::dmat3 frame = tangent_frame(pole);  // the pole is e3

    // The cap: the vertices nearest the pole.
    const std::size_t cap = std::min(n, std::max<std::size_t>(3, std::size_t(std::ceil(cap_fraction * double(n)))));
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::nth_element(order.begin(), order.begin() + std::ptrdiff_t(cap) - 1, order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return glm::dot(y[a], pole) > glm::dot(y[b], pole); });
    std::vector<std::uint8_t> pinned(n, 0);
    for (std::size_t i = 0; i < cap; ++i) pinned[order[i]] = 1;
    std::vector<glm::dvec2> chart(n);
    geo::parallel_for_chunks(n, kLevelChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t v = begin; v < end; ++v) chart[v] = chart_point(frame, y[v]);
    });
    ChartProblem problem = make_dirichlet_problem(level, pinned, chart);
    problem.frame = frame;
    return problem;
}

ChartProblem make_chart_problem(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, double cap_fraction) {
    return make_chart_problem(level, y, largest_triangle_pole(level, y), cap_fraction);
}

std::vector<glm::dvec3> sphere_points_from_chart(const ChartProblem& problem, const std::vector<glm::dvec3>& y,
                                                 const std::vector<glm::dvec2>& x) {
    std::vector<glm::dvec3> out = y;
    geo::parallel_for_chunks(problem.rows(), kLevelChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            out[problem.free_vertices[i]] =
                glm::normalize(problem.frame * linear_sphere::sphere_from_south_chart({x[i].x, x[i].y}));
    });
    return out;
}

}  // namespace gimg::passes::detail

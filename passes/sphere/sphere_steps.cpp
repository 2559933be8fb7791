// Per-vertex steps on the unit sphere (see sphere_steps.h).
#include "sphere/sphere_steps.h"

#include <cmath>

namespace gimg::passes::detail {

bool in_kernel(std::span<const std::uint32_t> faces, const std::vector<glm::uvec3>& triangles,
               const std::vector<glm::dvec3>& y, std::uint32_t v, const glm::dvec3& p) {
    for (std::uint32_t f : faces) {
        const glm::uvec3 t = triangles[f];
        const glm::dvec3& a = t.x == v ? p : y[t.x];
        const glm::dvec3& b = t.y == v ? p : y[t.y];
        const glm::dvec3& c = t.z == v ? p : y[t.z];
        if (!counter_clockwise(a, b, c)) return false;
    }
    return true;
}

VertexStep optimise_vertex(const VertexEnergy& e, double step, double tolerance, std::size_t max_iterations) {
    VertexStep r;
    r.position = e.origin;
    r.energy_before = r.energy_after = e.at_origin;
    if (!(e.abs_weight_sum > 0.0)) return r;
    double previous = r.energy_before;
    while (r.iterations < max_iterations) {
        // sum_u w_u (y(u) - y) = L - W (y - o), normalised by the weights.
        const glm::dvec3 laplacian = (e.laplacian - e.weight_sum * (r.position - e.origin)) / e.abs_weight_sum;
        const glm::dvec3 tangential = laplacian - glm::dot(laplacian, r.position) * r.position;
        const glm::dvec3 moved = r.position + step * tangential;
        const double length = glm::length(moved);
        if (!(length > 0.0) || !std::isfinite(length)) break;
        r.position = moved / length;
        ++r.iterations;
        const double energy = e.at(r.position);
        r.energy_after = energy;
        if (std::abs(energy - previous) < tolerance) break;
        previous = energy;
    }
    return r;
}

glm::dvec3 mass_centre(const std::vector<glm::dvec3>& y, std::span<const std::uint32_t> active) {
    glm::dvec3 c(0.0);
    for (std::uint32_t v : active) c += y[v];
    return active.empty() ? c : c / double(active.size());
}

double normalise_mass_centre(std::vector<glm::dvec3>& y, std::span<const std::uint32_t> active,
                             const std::vector<glm::uvec3>& triangles) {
    const glm::dvec3 c = mass_centre(y, active);
    if (!(glm::length(c) > 1e-15)) return 0.0;
    glm::dvec3 a = 0.75 * c;
    if (glm::length(a) > 0.5) a *= 0.5 / glm::length(a);  // big drifts go in several steps
    std::vector<glm::dvec3> moved(y);
    for (int attempt = 0; attempt < 8; ++attempt, a *= 0.5) {
        for (std::uint32_t v : active) moved[v] = moebius_move(y[v], a);
        if (all_counter_clockwise(triangles, moved)) {
            y.swap(moved);
            return glm::length(a);
        }
    }
    return 0.0;
}

bool all_counter_clockwise(const std::vector<glm::uvec3>& triangles, const std::vector<glm::dvec3>& y) {
    for (const glm::uvec3& t : triangles)
        if (!counter_clockwise(y[t.x], y[t.y], y[t.z])) return false;
    return true;
}

std::size_t count_flips(const std::vector<glm::uvec3>& triangles, const std::vector<glm::dvec3>& y) {
    std::size_t flips = 0;
    for (const glm::uvec3& t : triangles) flips += !(orientation(y[t.x], y[t.y], y[t.z]) > 0.0);
    return flips;
}

}  // namespace gimg::passes::detail

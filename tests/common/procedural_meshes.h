#pragma once
// Analytic shapes built in code, for tests and benchmarks whose answers are known in closed form.
// Faces are counter-clockwise seen from outside (from +z for the plane).

#include "gimg/geometry/mesh.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <utility>
#include <vector>

namespace gimg::test {

// Flips faces of a closed convex mesh around `center` so they face away from it.
inline void orient_outward(geo::Mesh& m, const glm::dvec3& center) {
    for (glm::uvec3& t : m.triangles) {
        const glm::dvec3 a = m.positions[t.x], b = m.positions[t.y], c = m.positions[t.z];
        if (glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0 - center) < 0.0) std::swap(t.y, t.z);
    }
}

// Icosahedron subdivided `level` times (each triangle into four), vertices projected onto the
// sphere: 20 * 4^level faces, 10 * 4^level + 2 vertices.
inline geo::Mesh make_icosphere(int level, double radius = 1.0, glm::dvec3 center = glm::dvec3(0.0)) {
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    geo::Mesh m;
    m.positions = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                   {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (auto& p : m.positions) p = glm::normalize(p);
    m.triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                   {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    orient_outward(m, glm::dvec3(0.0));
    for (int l = 0; l < level; ++l) {
        std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, inserted] = midpoint.try_emplace(key, 0u);
            if (inserted) {
                it->second = static_cast<std::uint32_t>(m.positions.size());
                m.positions.push_back(glm::normalize(m.positions[a] + m.positions[b]));
            }
            return it->second;
        };
        std::vector<glm::uvec3> next;
        next.reserve(4 * m.triangles.size());
        for (const glm::uvec3& t : m.triangles) {
            const std::uint32_t ab = mid(t.x, t.y), bc = mid(t.y, t.z), ca = mid(t.z, t.x);
            next.insert(next.end(), {{t.x, ab, ca}, {ab, t.y, bc}, {ca, bc, t.z}, {ab, bc, ca}});
        }
        m.triangles = std::move(next);
    }
    for (auto& p : m.positions) p = center + radius * p;
    return m;
}

// Latitude-longitude sphere: `segments` around, `rings` bands from pole to pole (rings >= 2),
// 2 * segments * (rings - 1) faces.
inline geo::Mesh make_uv_sphere(std::uint32_t segments, std::uint32_t rings, double radius = 1.0,
                                glm::dvec3 center = glm::dvec3(0.0)) {
    geo::Mesh m;
    m.positions.push_back(center + glm::dvec3(0, radius, 0));  // north pole
    for (std::uint32_t r = 1; r < rings; ++r) {
        const double phi = std::numbers::pi * r / rings;
        for (std::uint32_t s = 0; s < segments; ++s) {
            const double theta = 2.0 * std::numbers::pi * s / segments;
            m.positions.push_back(center + radius * glm::dvec3(std::sin(phi) * std::cos(theta), std::cos(phi),
                                                               std::sin(phi) * std::sin(theta)));
        }
    }
    const auto south = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(center + glm::dvec3(0, -radius, 0));
    auto at = [&](std::uint32_t r, std::uint32_t s) { return 1 + (r - 1) * segments + s % segments; };
    for (std::uint32_t s = 0; s < segments; ++s) {
        m.triangles.push_back({0, at(1, s + 1), at(1, s)});
        for (std::uint32_t r = 1; r + 1 < rings; ++r) {
            m.triangles.push_back({at(r, s), at(r, s + 1), at(r + 1, s)});
            m.triangles.push_back({at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)});
        }
        m.triangles.push_back({south, at(rings - 1, s), at(rings - 1, s + 1)});
    }
    orient_outward(m, center);
    return m;
}

// Axis-aligned box centred at the origin with the given side lengths: 8 vertices, 12 faces.
inline geo::Mesh make_box(glm::dvec3 size) {
    geo::Mesh m;
    const glm::dvec3 h = size / 2.0;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z});
    m.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 3, 7}, {1, 7, 5}};
    orient_outward(m, glm::dvec3(0.0));
    return m;
}

// Grid of nx by ny squares of side `cell` in the z = 0 plane from the origin, two triangles per
// square: (nx + 1)(ny + 1) vertices, 2 nx ny faces, normals +z.
inline geo::Mesh make_plane_grid(std::uint32_t nx, std::uint32_t ny, double cell = 1.0) {
    geo::Mesh m;
    for (std::uint32_t j = 0; j <= ny; ++j)
        for (std::uint32_t i = 0; i <= nx; ++i) m.positions.push_back({i * cell, j * cell, 0.0});
    auto at = [&](std::uint32_t i, std::uint32_t j) { return j * (nx + 1) + i; };
    for (std::uint32_t j = 0; j < ny; ++j)
        for (std::uint32_t i = 0; i < nx; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return m;
}

}  // namespace gimg::test

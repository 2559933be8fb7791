#pragma once
// The analytic cylindrical-projection cases, each checked against its closed form: every covered
// pixel's d and the coverage row by row. Shared by every method (the GPU Z-buffer, the paper's
// CPU scanline algorithm), each test passing its own projector.
#include "cylinder_cases.h"

#include "gimg/passes/cylinder.h"

#include <glm/ext/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <random>

namespace gimg::test {

// Projects a mesh (already in the cylinder frame) to a W x H cylindrical image. The checks that
// take a tolerance compare d with the closed form to it: 2e-6 for arithmetic in double (the
// inputs are float32), 5e-5 for the z-buffer's float32 path (test_cylinder_meshes.cpp says why).
using Projector = std::function<passes::CylinderImage(const geo::Mesh&, std::uint32_t, std::uint32_t)>;

inline geo::Mesh transformed(geo::Mesh m, const glm::dmat4& t) {
    for (auto& p : m.positions) p = glm::dvec3(t * glm::dvec4(p, 1.0));
    return m;
}

inline void check_sphere_centred_on_the_axis(const Projector& project) {
    const double r = 0.4, y0 = 0.5;
    const geo::Mesh sphere = geo::make_icosphere(r, 5, {0.0, y0, 0.0});
    // The inscribed polyhedron lies between the sphere and its faces' smallest distance to the centre.
    double r_in = r;
    for (const auto& t : sphere.triangles) {
        const glm::dvec3 n = glm::normalize(
            glm::cross(sphere.positions[t.y] - sphere.positions[t.x], sphere.positions[t.z] - sphere.positions[t.x]));
        r_in = std::min(r_in, std::abs(glm::dot(n, sphere.positions[t.x] - glm::dvec3(0, y0, 0))));
    }
    const std::uint32_t W = 256, H = 128;
    const auto img = project(sphere, W, H);
    std::size_t checked = 0;
    for (std::uint32_t v = 0; v < H; ++v) {
        const double dy = y_of(v, H) - y0;
        for (std::uint32_t u = 0; u < W; ++u) {
            const std::size_t i = img.index(u, v);
            if (std::abs(dy) < r_in) {
                ASSERT_TRUE(img.covered[i]) << u << "," << v;
                const double d = img.distance[i];
                EXPECT_LE(d, std::sqrt(r * r - dy * dy) + 1e-6);
                EXPECT_GE(d, std::sqrt(r_in * r_in - dy * dy) - 1e-6);
                ++checked;
            } else if (std::abs(dy) > r) {
                ASSERT_FALSE(img.covered[i]) << u << "," << v;
            }
        }
    }
    EXPECT_GT(checked, W * 80u);
}

inline void check_cube_around_the_axis(const Projector& project, double tolerance) {
    const double a = 0.3;
    // y from 0.3 to 0.7: no row of the image lies exactly on the top or bottom face.
    const geo::Mesh cube =
        transformed(geo::make_box({2 * a, 0.4, 2 * a}, 4), glm::translate(glm::dmat4(1.0), {0, 0.5, 0}));
    const std::uint32_t W = 360, H = 90;
    const auto img = project(cube, W, H);
    for (std::uint32_t v = 0; v < H; ++v) {
        const double y = y_of(v, H);
        const bool inside = y > 0.3 && y < 0.7;
        for (std::uint32_t u = 0; u < W; ++u) {
            const std::size_t i = img.index(u, v);
            ASSERT_EQ(bool(img.covered[i]), inside) << u << "," << v;
            if (!inside) continue;
            const double th = theta_of(u, W);
            const double expected = a / std::max(std::abs(std::cos(th)), std::abs(std::sin(th)));
            ASSERT_NEAR(img.distance[i], expected, tolerance) << u << "," << v;
        }
    }
}

inline void check_sphere_off_the_axis(const Projector& project) {
    const double r = 0.25, cx = 0.5, y0 = 0.5;
    const geo::Mesh sphere = geo::make_icosphere(r, 6, {cx, y0, 0.0});
    const std::uint32_t W = 512, H = 128;
    const auto img = project(sphere, W, H);
    std::size_t front = 0, back = 0;
    for (std::uint32_t v = 0; v < H; ++v) {
        const double dy = y_of(v, H) - y0;
        if (std::abs(dy) > 0.9 * r) continue;  // away from the poles, where tessellation dominates
        const double rho = std::sqrt(r * r - dy * dy);
        for (std::uint32_t u = 0; u < W; ++u) {
            const double th = theta_of(u, W);
            const double disc = rho * rho - cx * cx * std::sin(th) * std::sin(th);
            const std::size_t i = img.index(u, v);
            if (disc < 0.02 * rho * rho) continue;  // near the silhouette
            ASSERT_TRUE(img.covered[i]) << u << "," << v;
            const double expected = cx * std::cos(th) + std::sqrt(disc);
            // Inscribed polyhedron (level 6): within 2e-4 r of the sphere along the line.
            EXPECT_NEAR(img.distance[i], expected, 2e-3 * r) << u << "," << v;
            (expected > 0 ? front : back)++;
        }
    }
    EXPECT_GT(front, 1000u);
    EXPECT_GT(back, 1000u);  // back projection (d < 0) really happened
}

inline void check_tilted_plate_through_the_axis(const Projector& project, double tolerance) {
    // A thin box tilted 35 degrees about z and 20 about y, pierced by the axis.
    const glm::dmat4 rot =
        glm::rotate(glm::rotate(glm::dmat4(1.0), glm::radians(20.0), {0, 1, 0}), glm::radians(35.0), {0, 0, 1});
    const glm::dmat4 model = glm::translate(glm::dmat4(1.0), {0.0, 0.5, 0.0}) * rot;
    const glm::dvec3 half{0.45, 0.02, 0.3};
    const geo::Mesh plate = transformed(geo::make_box(2.0 * half, 6), model);
    const glm::dvec3 axes[3] = {glm::dvec3(rot[0]), glm::dvec3(rot[1]), glm::dvec3(rot[2])};
    const std::uint32_t W = 400, H = 200;
    const auto img = project(plate, W, H);
    std::size_t covered = 0, mismatched = 0;
    for (std::uint32_t v = 0; v < H; ++v)
        for (std::uint32_t u = 0; u < W; ++u) {
            const auto expected = gimg::test::box_entry({0.0, 0.5, 0.0}, axes, half, theta_of(u, W), y_of(v, H));
            const std::size_t i = img.index(u, v);
            if (bool(img.covered[i]) != expected.has_value()) {
                ++mismatched;  // only where the line grazes an edge of the box
                if (mismatched < 6)
                    std::printf("mismatch at %u,%u: got %s %g, exact %s %g\n", u, v, img.covered[i] ? "hit" : "miss",
                                img.distance[i], expected ? "hit" : "miss", expected ? *expected : 0.0);
                continue;
            }
            if (!expected) continue;
            ++covered;
            ASSERT_NEAR(img.distance[i], *expected, tolerance) << u << "," << v;
        }
    EXPECT_GT(covered, 5000u);
    std::printf("plate: %zu covered pixels, %zu differ in coverage from the exact box\n", covered, mismatched);
    EXPECT_LE(mismatched, covered / 10000) << "coverage differs from the exact box at " << mismatched << " pixels";
}

inline void check_cone_distance_linear_in_height(const Projector& project, double tolerance) {
    // A cone (n facets) with its apex on the axis at y = 0.9 and its base (radius 0.5) at y = 0.1.
    const int n = 48;
    geo::Mesh cone;
    cone.positions.push_back({0.0, 0.9, 0.0});
    cone.positions.push_back({0.0, 0.1, 0.0});
    for (int k = 0; k < n; ++k) {
        const double a = 2.0 * std::numbers::pi * (k + 0.5) / n;  // a facet edge off theta = 0
        cone.positions.push_back({0.5 * std::cos(a), 0.1, 0.5 * std::sin(a)});
    }
    for (unsigned k = 0; k < unsigned(n); ++k) {
        const unsigned a = 2 + k, b = 2 + (k + 1) % n;
        cone.triangles.push_back({0, b, a});  // sides face outwards
        cone.triangles.push_back({1, a, b});  // base faces down
    }
    const std::uint32_t W = 240, H = 100;
    const auto img = project(cone, W, H);
    for (std::uint32_t u = 0; u < W; ++u) {
        // Along a column the facet seen is fixed, so d(y) = d_base (0.9 - y) / 0.8 exactly.
        const std::uint32_t v_base = H - 12;  // y = 0.115
        ASSERT_TRUE(img.covered[img.index(u, v_base)]);
        const double d_base = img.distance[img.index(u, v_base)] / ((0.9 - y_of(v_base, H)) / 0.8);
        EXPECT_NEAR(d_base,
                    0.5 * std::cos(std::numbers::pi / n) /
                        std::cos(theta_of(u, W) - 2.0 * std::numbers::pi *
                                                      std::round(theta_of(u, W) / (2.0 * std::numbers::pi / n)) / n),
                    1e-5);
        for (std::uint32_t v = 12; v < v_base; ++v) {
            const double y = y_of(v, H);
            ASSERT_TRUE(img.covered[img.index(u, v)]) << u << "," << v;
            ASSERT_NEAR(img.distance[img.index(u, v)], d_base * (0.9 - y) / 0.8, tolerance) << u << "," << v;
        }
    }
}

inline void check_every_line_through_a_shared_edge(const Projector& project, double tolerance) {
    // A closed-sided prism with one vertical edge on every column's lines (at theta_u exactly, up to
    // rounding) and uneven radii: each pixel's line passes through the edge two facets share, and
    // must hit it (a test that is not watertight lets such lines through).
    const std::uint32_t W = 360, H = 90;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> radius(0.4, 0.8);
    geo::Mesh prism;
    std::vector<double> r(W);
    for (std::uint32_t u = 0; u < W; ++u) {
        r[u] = radius(rng);
        const double th = theta_of(u, W);
        prism.positions.push_back({r[u] * std::cos(th), 0.1, r[u] * std::sin(th)});
        prism.positions.push_back({r[u] * std::cos(th), 0.9, r[u] * std::sin(th)});
    }
    for (unsigned u = 0; u < W; ++u) {
        const unsigned b0 = 2 * u, t0 = b0 + 1, b1 = 2 * ((u + 1) % W), t1 = b1 + 1;
        prism.triangles.push_back({b0, t0, b1});  // facing outwards
        prism.triangles.push_back({b1, t0, t1});
    }
    const auto img = project(prism, W, H);
    std::size_t missed = 0;
    for (std::uint32_t v = 0; v < H; ++v) {
        const double y = y_of(v, H);
        if (y < 0.11 || y > 0.89) continue;
        for (std::uint32_t u = 0; u < W; ++u) {
            if (!img.covered[img.index(u, v)]) {
                ++missed;
                continue;
            }
            ASSERT_NEAR(img.distance[img.index(u, v)], r[u], tolerance) << u << "," << v;
        }
    }
    EXPECT_EQ(missed, 0u) << "lines through a shared edge that hit neither facet";
}

inline void check_cylindrical_shell_across_the_seam(const Projector& project, double tolerance) {
    // A thick tube, inner radius 0.5, outer 0.7, 36 facets with one facet centred on theta = 0.
    const int n = 36;
    const double r_in = 0.5, r_out = 0.7, y0 = 0.2, y1 = 0.8;
    geo::Mesh shell;
    auto ring = [&](double r, double y) {
        for (int k = 0; k < n; ++k) {
            const double a = 2.0 * std::numbers::pi * (k + 0.5) / n;
            shell.positions.push_back({r * std::cos(a), y, r * std::sin(a)});
        }
    };
    ring(r_out, y0), ring(r_out, y1), ring(r_in, y0), ring(r_in, y1);
    auto id = [&](int ring_index, int k) { return unsigned(ring_index * n + (k % n)); };
    for (int k = 0; k < n; ++k) {
        auto quad = [&](unsigned a, unsigned b, unsigned c, unsigned d) {
            shell.triangles.push_back({a, b, c});
            shell.triangles.push_back({a, c, d});
        };
        quad(id(0, k), id(1, k), id(1, k + 1), id(0, k + 1));  // outer wall, normal outwards
        quad(id(2, k), id(2, k + 1), id(3, k + 1), id(3, k));  // inner wall, normal towards the axis
        quad(id(1, k), id(3, k), id(3, k + 1), id(1, k + 1));  // top cap
        quad(id(0, k), id(0, k + 1), id(2, k + 1), id(2, k));  // bottom cap
    }
    const std::uint32_t W = 720, H = 60;
    const auto img = project(shell, W, H);
    for (std::uint32_t v = 0; v < H; ++v) {
        const double y = y_of(v, H);
        const bool inside = y > y0 && y < y1;
        for (std::uint32_t u = 0; u < W; ++u) {
            const std::size_t i = img.index(u, v);
            ASSERT_EQ(bool(img.covered[i]), inside) << u << "," << v;
            if (!inside) continue;
            const double th = theta_of(u, W), step = 2.0 * std::numbers::pi / n;
            const double facet = std::round(th / step) * step;  // facet centres at multiples of 10 degrees
            ASSERT_NEAR(img.distance[i], r_out * std::cos(step / 2) / std::cos(th - facet), tolerance) << u << "," << v;
        }
    }
}

}  // namespace gimg::test

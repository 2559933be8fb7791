#include "gimg/geometry/shapes.h"

#include "gimg/geometry/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <map>
#include <numbers>
#include <utility>

namespace gimg::geo {

Mesh make_icosphere(double radius, int level, glm::dvec3 center) {
    if (level < 0 || level > 9) throw InputError("icosphere level must be in 0..9");
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<glm::dvec3> p{{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    std::vector<glm::uvec3> f{{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (auto& v : p) v = glm::normalize(v);
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<unsigned, unsigned>, unsigned> midpoints;
        auto midpoint = [&](unsigned a, unsigned b) {
            auto key = std::minmax(a, b);
            auto [it, inserted] = midpoints.try_emplace(key, unsigned(p.size()));
            if (inserted) p.push_back(glm::normalize(p[a] + p[b]));
            return it->second;
        };
        std::vector<glm::uvec3> next;
        next.reserve(f.size() * 4);
        for (const auto& tri : f) {
            unsigned ab = midpoint(tri.x, tri.y), bc = midpoint(tri.y, tri.z), ca = midpoint(tri.z, tri.x);
            next.push_back({tri.x, ab, ca});
            next.push_back({tri.y, bc, ab});
            next.push_back({tri.z, ca, bc});
            next.push_back({ab, bc, ca});
        }
        f.swap(next);
    }
    Mesh m;
    m.positions.reserve(p.size());
    for (const auto& v : p) m.positions.push_back(center + radius * v);
    m.triangles = std::move(f);
    return m;
}

Mesh make_uv_sphere(int segments, int rings, double radius, glm::dvec3 center) {
    if (segments < 3 || rings < 2) throw InputError("a uv sphere needs at least 3 segments and 2 rings");
    Mesh m;
    m.positions.push_back(center + glm::dvec3(0, radius, 0));  // north pole
    for (int r = 1; r < rings; ++r) {
        const double phi = std::numbers::pi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double theta = 2.0 * std::numbers::pi * s / segments;
            m.positions.push_back(center + radius * glm::dvec3(std::sin(phi) * std::cos(theta), std::cos(phi),
                                                               std::sin(phi) * std::sin(theta)));
        }
    }
    const unsigned south = unsigned(m.positions.size());
    m.positions.push_back(center + glm::dvec3(0, -radius, 0));
    auto at = [&](int r, int s) { return unsigned(1 + (r - 1) * segments + s % segments); };
    // Seen from outside, increasing theta runs clockwise when looking down y: order faces so
    // their normals point away from the centre.
    for (int s = 0; s < segments; ++s) {
        m.triangles.push_back({0, at(1, s + 1), at(1, s)});
        for (int r = 1; r + 1 < rings; ++r) {
            m.triangles.push_back({at(r, s), at(r, s + 1), at(r + 1, s)});
            m.triangles.push_back({at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)});
        }
        m.triangles.push_back({south, at(rings - 1, s), at(rings - 1, s + 1)});
    }
    return m;
}

Mesh make_box(glm::dvec3 size, int divisions) {
    if (divisions < 1) throw InputError("box divisions must be at least 1");
    Mesh m;
    std::map<std::tuple<long, long, long>, unsigned> index;  // shared vertices on the lattice
    const int n = divisions;
    auto vertex = [&](int i, int j, int k) {
        auto [it, inserted] = index.try_emplace({i, j, k}, unsigned(m.positions.size()));
        if (inserted)
            m.positions.push_back(
                {(double(i) / n - 0.5) * size.x, (double(j) / n - 0.5) * size.y, (double(k) / n - 0.5) * size.z});
        return it->second;
    };
    // Each face: a fixed axis at 0 or n, two running axes chosen so the normal points outward.
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
            for (int a = 0; a < n; ++a) {
                for (int b = 0; b < n; ++b) {
                    auto at = [&](int du, int dv) {
                        int c[3];
                        c[axis] = side * n;
                        c[u_axis] = a + du;
                        c[v_axis] = b + dv;
                        return vertex(c[0], c[1], c[2]);
                    };
                    unsigned q00 = at(0, 0), q10 = at(1, 0), q11 = at(1, 1), q01 = at(0, 1);
                    if (side == 1) {
                        m.triangles.push_back({q00, q10, q11});
                        m.triangles.push_back({q00, q11, q01});
                    } else {
                        m.triangles.push_back({q00, q11, q10});
                        m.triangles.push_back({q00, q01, q11});
                    }
                }
            }
        }
    }
    return m;
}

Mesh make_grid(int nx, int ny, double width, double height) {
    if (nx < 1 || ny < 1) throw InputError("grid needs at least one quad each way");
    Mesh m;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            const double u = double(i) / nx, v = double(j) / ny;
            m.positions.push_back({u * width, v * height, 0.0});
            m.texcoords.push_back({u, v});
        }
    auto id = [&](int i, int j) { return unsigned(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

Mesh make_torus(double R, double r, int n_ring, int n_tube) {
    if (n_ring < 3 || n_tube < 3) throw InputError("torus needs at least 3 segments each way");
    Mesh m;
    const double two_pi = 2.0 * std::numbers::pi;
    for (int i = 0; i < n_ring; ++i)
        for (int j = 0; j < n_tube; ++j) {
            const double a = two_pi * i / n_ring, b = two_pi * j / n_tube;
            const double d = R + r * std::cos(b);
            m.positions.push_back({d * std::cos(a), r * std::sin(b), -d * std::sin(a)});
        }
    auto id = [&](int i, int j) { return unsigned((i % n_ring) * n_tube + (j % n_tube)); };
    for (int i = 0; i < n_ring; ++i)
        for (int j = 0; j < n_tube; ++j) {
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

}  // namespace gimg::geo

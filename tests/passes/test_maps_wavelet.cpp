// MAPS semi-regular remesh and k-disk wavelets (spec sec. 2.9 items 4-5): 4-to-1 subdivision
// counts, topology and exact base coordinates; perfect reconstruction, the lazy wavelet as
// subsampling, zero details on a linear subdivision, orthogonality against an independently
// assembled Gram matrix, the one-level-down error falling with k, the GPU against the CPU twin,
// and keeping the largest details.
#include "gpu_test.h"

#include "gimg/engine/graph.h"
#include "gimg/engine/texel_array.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/maps.h"

#include <Eigen/Sparse>
#include <glm/geometric.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

using namespace gimg;
namespace gp = gimg::passes;

namespace {

class MapsWaveletGpu : public gimg::test::GpuTest {};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t(a) << 32 | b) : (std::uint64_t(b) << 32 | a);
}

// The position of a base point when the base's triangles are flat.
glm::dvec3 on_base(const geo::Mesh& base, const gp::SurfacePoint& p) {
    const glm::uvec3 t = base.triangles[p.face];
    return base.positions[t[0]] * p.bary.x + base.positions[t[1]] * p.bary.y + base.positions[t[2]] * p.bary.z;
}

// Every remesh vertex at its flat base point: exactly the linear subdivision of the base.
void place_linearly(gp::SemiRegularMesh& mesh, const geo::Mesh& base) {
    mesh.positions.clear();
    for (const gp::SurfacePoint& p : mesh.base_point) mesh.positions.push_back(on_base(base, p));
}

// A bumpy sphere sampled through the base points (smooth), plus uniform noise of `noise`.
gp::SemiRegularMesh curved_remesh(std::uint32_t levels, double noise, std::uint32_t seed = 5) {
    const geo::Mesh base = geo::make_icosphere(1.0, 0);
    gp::SemiRegularMesh mesh = gp::subdivide_base(base, levels);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-noise, noise);
    for (const gp::SurfacePoint& p : mesh.base_point) {
        const glm::dvec3 u = glm::normalize(on_base(base, p));
        const double r = 1.0 + 0.15 * std::sin(3.0 * u.x) * std::cos(2.0 * u.y + u.z);
        mesh.positions.push_back(u * r + glm::dvec3(jitter(rng), jitter(rng), jitter(rng)));
    }
    return mesh;
}

double diagonal(const std::vector<glm::dvec3>& p) {
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const glm::dvec3& x : p) lo = glm::min(lo, x), hi = glm::max(hi, x);
    return glm::distance(lo, hi);
}

double max_difference(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b, std::size_t count) {
    double worst = 0.0;
    for (std::size_t i = 0; i < count; ++i) worst = std::max(worst, glm::length(a[i] - b[i]));
    return worst;
}

// The Gram matrix of the level-j hats in the spec's inner product, assembled from scratch: every
// level-j triangle has normalised area 4^-j, and P1 mass entries are area/12 (1 + [r == s]).
Eigen::SparseMatrix<double> mass(const gp::SemiRegularMesh& mesh, std::uint32_t j) {
    const double area = std::ldexp(1.0, -2 * int(j));
    std::vector<Eigen::Triplet<double>> entries;
    for (const glm::uvec3& t : mesh.faces[j])
        for (int r = 0; r < 3; ++r)
            for (int s = 0; s < 3; ++s) entries.emplace_back(t[r], t[s], area / 12.0 * (r == s ? 2.0 : 1.0));
    Eigen::SparseMatrix<double> m(mesh.vertex_count[j], mesh.vertex_count[j]);
    m.setFromTriplets(entries.begin(), entries.end());
    return m;
}

// Level j+1 values of the level-j hat at i: 1 at i, 1/2 at the midpoints of its edges.
Eigen::VectorXd coarse_hat(const gp::SemiRegularMesh& mesh, std::uint32_t j, std::uint32_t i) {
    Eigen::VectorXd h = Eigen::VectorXd::Zero(mesh.vertex_count[j + 1]);
    h(i) = 1.0;
    for (std::uint32_t m = mesh.vertex_count[j]; m < mesh.vertex_count[j + 1]; ++m) {
        const glm::uvec2 p = mesh.parents[m - mesh.vertex_count[0]];
        if (p.x == i || p.y == i) h(m) = 0.5;
    }
    return h;
}

// The squared L2 distance of two level-J piecewise-linear surfaces, all three coordinates.
double l2_squared(const Eigen::SparseMatrix<double>& m, const std::vector<glm::dvec3>& a,
                  const std::vector<glm::dvec3>& b) {
    double sum = 0.0;
    for (int c = 0; c < 3; ++c) {
        Eigen::VectorXd e(Eigen::Index(a.size()));
        for (std::size_t i = 0; i < a.size(); ++i) e(Eigen::Index(i)) = a[i][c] - b[i][c];
        sum += e.dot(m * e);
    }
    return sum;
}

// D_k(m) by breadth-first search over level j's edges, independently of wavelet_filters.
std::set<std::uint32_t> disk(const gp::SemiRegularMesh& mesh, std::uint32_t j, std::uint32_t m, int k) {
    std::map<std::uint32_t, std::set<std::uint32_t>> ring;
    for (const glm::uvec3& t : mesh.faces[j])
        for (int r = 0; r < 3; ++r) ring[t[r]].insert({t[(r + 1) % 3], t[(r + 2) % 3]});
    const glm::uvec2 p = mesh.parents[m - mesh.vertex_count[0]];
    std::set<std::uint32_t> d{p.x, p.y};
    for (int step = 0; step < k; ++step) {
        std::set<std::uint32_t> grown = d;
        for (std::uint32_t v : d) grown.insert(ring[v].begin(), ring[v].end());
        d = grown;
    }
    return d;
}

// The weights s_{., m} of one odd vertex, read back from the CSR rows.
std::map<std::uint32_t, double> weights_of(const gp::WaveletFilters& f, std::uint32_t j, std::uint32_t m) {
    std::map<std::uint32_t, double> out;
    const auto& l = f.levels[j];
    for (std::uint32_t i = 0; i + 1 < l.offsets.size(); ++i)
        for (std::uint32_t e = l.offsets[i]; e < l.offsets[i + 1]; ++e)
            if (l.odd[e] == m) out[i] = l.weight[e];
    return out;
}

constexpr int kAllWavelets[] = {-1, 0, 1, 2};

}  // namespace

TEST(SemiRegular, CountsTopologyAndParentsOnEveryLevel) {
    // The icosahedron (Euler characteristic 2) and a coarse torus (0).
    for (const geo::Mesh& base : {geo::make_icosphere(1.0, 0), geo::make_torus(1.0, 0.35, 6, 4)}) {
        const gp::SemiRegularMesh mesh = gp::subdivide_base(base, 4);
        ASSERT_EQ(mesh.levels(), 4u);
        ASSERT_EQ(mesh.vertex_count.size(), 5u);
        EXPECT_EQ(mesh.vertex_count[0], base.vertex_count());
        EXPECT_EQ(mesh.faces[0], base.triangles);
        EXPECT_EQ(mesh.parents.size(), mesh.vertex_count.back() - mesh.vertex_count[0]);
        EXPECT_EQ(mesh.base_point.size(), mesh.vertex_count.back());
        EXPECT_TRUE(mesh.positions.empty());
        const long euler = long(base.vertex_count()) - long(base.face_count()) * 3 / 2 + long(base.face_count());
        std::size_t previous_edges = 0;
        for (std::uint32_t j = 0; j <= 4; ++j) {
            const std::uint32_t v = mesh.vertex_count[j];
            EXPECT_EQ(mesh.faces[j].size(), base.face_count() << (2 * j));
            // Every undirected edge in exactly two faces, once in each direction; every id used.
            std::map<std::uint64_t, int> uses;
            std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
            std::vector<bool> used(v, false);
            for (const glm::uvec3& t : mesh.faces[j])
                for (int r = 0; r < 3; ++r) {
                    ASSERT_LT(t[r], v);
                    used[t[r]] = true;
                    ++uses[edge_key(t[r], t[(r + 1) % 3])];
                    EXPECT_TRUE(directed.insert({t[r], t[(r + 1) % 3]}).second) << "level " << j;
                }
            for (const auto& [key, n] : uses) EXPECT_EQ(n, 2) << "level " << j;
            EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
            const std::size_t edges = uses.size();
            EXPECT_EQ(long(v) - long(edges) + long(mesh.faces[j].size()), euler) << "level " << j;
            if (j > 0) {
                EXPECT_EQ(edges, 2 * previous_edges + 3 * mesh.faces[j - 1].size());
            }
            previous_edges = edges;
            if (j == 4) break;
            EXPECT_EQ(mesh.vertex_count[j + 1], v + edges);
            // Each odd vertex of level j+1 is the midpoint of its own level-j edge, and splits it.
            std::set<std::uint64_t> split;
            std::set<std::uint64_t> fine_edges;
            for (const glm::uvec3& t : mesh.faces[j + 1])
                for (int r = 0; r < 3; ++r) fine_edges.insert(edge_key(t[r], t[(r + 1) % 3]));
            for (std::uint32_t m = v; m < mesh.vertex_count[j + 1]; ++m) {
                const glm::uvec2 p = mesh.parents[m - mesh.vertex_count[0]];
                EXPECT_TRUE(uses.count(edge_key(p.x, p.y))) << "odd " << m;
                EXPECT_TRUE(split.insert(edge_key(p.x, p.y)).second) << "odd " << m;
                EXPECT_TRUE(fine_edges.count(edge_key(p.x, m)) && fine_edges.count(edge_key(m, p.y))) << "odd " << m;
            }
        }
    }
}

TEST(SemiRegular, BasePointsAreExactAndFacesKeepTheBaseOrientation) {
    const geo::Mesh base = geo::make_icosphere(1.0, 0);
    gp::SemiRegularMesh mesh = gp::subdivide_base(base, 3);
    for (std::uint32_t v = 0; v < mesh.vertex_count.back(); ++v) {
        const gp::SurfacePoint& p = mesh.base_point[v];
        ASSERT_LT(p.face, base.face_count());
        for (int c = 0; c < 3; ++c) {
            EXPECT_GE(p.bary[c], 0.0);
            EXPECT_EQ(p.bary[c] * 8.0, std::floor(p.bary[c] * 8.0)) << "vertex " << v << " not dyadic";
        }
        EXPECT_EQ(p.bary.x + p.bary.y + p.bary.z, 1.0) << "vertex " << v;
    }
    for (std::uint32_t v = 0; v < mesh.vertex_count[0]; ++v) {
        const gp::SurfacePoint& p = mesh.base_point[v];
        const int corner = p.bary.x == 1.0 ? 0 : p.bary.y == 1.0 ? 1 : 2;
        EXPECT_EQ(p.bary[corner], 1.0);
        EXPECT_EQ(base.triangles[p.face][corner], v);
    }
    place_linearly(mesh, base);
    // Midpoints land on their parents' midpoints, whichever base triangle records them.
    for (std::uint32_t m = mesh.vertex_count[0]; m < mesh.vertex_count.back(); ++m) {
        const glm::uvec2 p = mesh.parents[m - mesh.vertex_count[0]];
        EXPECT_LE(glm::distance(mesh.positions[m], 0.5 * (mesh.positions[p.x] + mesh.positions[p.y])), 1e-15);
    }
    // Counter-clockwise from outside, as the base: every face's normal points away from the centre.
    for (std::uint32_t j = 1; j <= 3; ++j) {
        const geo::Mesh level = mesh.level_mesh(j);
        EXPECT_EQ(level.vertex_count(), mesh.vertex_count[j]);
        for (const glm::uvec3& t : level.triangles) {
            const glm::dvec3 a = level.positions[t[0]], b = level.positions[t[1]], c = level.positions[t[2]];
            EXPECT_GT(glm::dot(glm::cross(b - a, c - a), a + b + c), 0.0);
        }
    }
}

TEST(SemiRegular, RejectsBadInput) {
    const geo::Mesh base = geo::make_icosphere(1.0, 0);
    EXPECT_THROW(gp::subdivide_base(base, 9), geo::InputError);
    geo::Mesh broken = base;
    broken.triangles[3][1] = 12;
    EXPECT_THROW(gp::subdivide_base(broken, 1), geo::InputError);
    gp::SemiRegularMesh mesh = gp::subdivide_base(base, 1);
    EXPECT_THROW(mesh.level_mesh(0), geo::InputError);  // not mapped yet
    place_linearly(mesh, base);
    EXPECT_THROW(mesh.level_mesh(2), geo::InputError);
    EXPECT_EQ(mesh.level_mesh(0).positions, base.positions);
    EXPECT_THROW(gp::wavelet_filters(mesh, 3), geo::InputError);
    EXPECT_THROW(gp::wavelet_filters(gp::SemiRegularMesh{}, 1), geo::InputError);
    std::vector<glm::dvec3> short_values(5);
    EXPECT_THROW(gp::wavelet_analysis(mesh, gp::wavelet_filters(mesh, 1), short_values), geo::InputError);
    const gp::WaveletFilters other = gp::wavelet_filters(gp::subdivide_base(base, 2), 1);
    std::vector<glm::dvec3> values = mesh.positions;
    EXPECT_THROW(gp::wavelet_analysis(mesh, other, values), geo::InputError);
}

TEST(MapsWavelet, FiltersCoverTheKDisks) {
    const gp::SemiRegularMesh mesh = gp::subdivide_base(geo::make_icosphere(1.0, 0), 3);
    const gp::WaveletFilters lazy = gp::wavelet_filters(mesh, -1);
    EXPECT_EQ(lazy.k, -1);
    ASSERT_EQ(lazy.levels.size(), 3u);
    for (std::uint32_t j = 0; j < 3; ++j) {
        EXPECT_EQ(lazy.levels[j].offsets, std::vector<std::uint32_t>(mesh.vertex_count[j] + 1, 0));
        EXPECT_TRUE(lazy.levels[j].weight.empty());
    }
    for (int k : {0, 1, 2}) {
        const gp::WaveletFilters f = gp::wavelet_filters(mesh, k);
        EXPECT_EQ(f.k, k);
        for (std::uint32_t j = 0; j < 3; ++j)
            for (std::uint32_t m = mesh.vertex_count[j]; m < mesh.vertex_count[j + 1]; m += 7) {
                std::set<std::uint32_t> rows;
                for (const auto& [i, s] : weights_of(f, j, m)) rows.insert(i);
                EXPECT_EQ(rows, disk(mesh, j, m, k)) << "k " << k << " odd " << m;
            }
    }
    // k = 0 between two valence-6 vertices: G = [[1, 1/6], [1/6, 1]], b = (5/24, 5/24), s = 5/28.
    const gp::WaveletFilters f0 = gp::wavelet_filters(mesh, 0);
    int checked = 0;
    for (std::uint32_t m = mesh.vertex_count[2]; m < mesh.vertex_count[3]; ++m) {
        const glm::uvec2 p = mesh.parents[m - mesh.vertex_count[0]];
        if (p.x < mesh.vertex_count[0] || p.y < mesh.vertex_count[0]) continue;  // valence 5
        for (const auto& [i, s] : weights_of(f0, 2, m)) EXPECT_NEAR(s, 5.0 / 28.0, 1e-15);
        ++checked;
    }
    EXPECT_GT(checked, 100);
}

TEST(MapsWavelet, WaveletsAreOrthogonalToTheScalingFunctionsOfTheirDisk) {
    const gp::SemiRegularMesh mesh = gp::subdivide_base(geo::make_icosphere(1.0, 0), 2);
    for (std::uint32_t j = 0; j < 2; ++j) {
        const Eigen::SparseMatrix<double> m1 = mass(mesh, j + 1);
        const double scale = std::ldexp(1.0, -2 * int(j));  // a coarse triangle's area
        std::vector<Eigen::VectorXd> hats;
        for (std::uint32_t i = 0; i < mesh.vertex_count[j]; ++i) hats.push_back(coarse_hat(mesh, j, i));
        // The independent Gram matrix reproduces the coarse hats' own products (refinement relation).
        const Eigen::SparseMatrix<double> m0 = mass(mesh, j);
        for (std::uint32_t i = 0; i < mesh.vertex_count[j]; i += 5)
            for (std::uint32_t l = 0; l < mesh.vertex_count[j]; ++l)
                EXPECT_NEAR(hats[i].dot(m1 * hats[l]), m0.coeff(i, l), 1e-15);
        for (int k : {-1, 0, 1, 2}) {
            const gp::WaveletFilters f = gp::wavelet_filters(mesh, k);
            double worst = 0.0, lazy_least = 1e300;
            for (std::uint32_t m = mesh.vertex_count[j]; m < mesh.vertex_count[j + 1]; ++m) {
                Eigen::VectorXd psi = Eigen::VectorXd::Zero(mesh.vertex_count[j + 1]);
                psi(m) = 1.0;
                for (const auto& [i, s] : weights_of(f, j, m)) psi -= s * hats[i];
                const Eigen::VectorXd mpsi = m1 * psi;
                for (std::uint32_t i : disk(mesh, j, m, std::max(k, 0))) {
                    const double product = std::abs(mpsi.dot(hats[i])) / scale;
                    if (k < 0)
                        lazy_least = std::min(lazy_least, product);
                    else
                        worst = std::max(worst, product);
                }
            }
            if (k < 0) {
                EXPECT_GT(lazy_least, 0.05) << "the lazy wavelet is not orthogonal to its parents' hats";
            } else {
                EXPECT_LE(worst, 1e-14) << "k " << k << " level " << j;
            }
        }
    }
}

TEST(MapsWavelet, AnalysisThenSynthesisReconstructsPerfectly) {
    const gp::SemiRegularMesh mesh = curved_remesh(4, 0.02);
    const double tolerance = 1e-12 * diagonal(mesh.positions);
    for (int k : kAllWavelets) {
        const gp::WaveletFilters f = gp::wavelet_filters(mesh, k);
        for (std::uint32_t level : {0u, 2u}) {
            std::vector<glm::dvec3> values = mesh.positions;
            gp::wavelet_analysis(mesh, f, values, level);
            // Details of the noise are far from zero: the transform did something.
            EXPECT_GT(max_difference(values, mesh.positions, values.size()), 1e-3);
            gp::wavelet_synthesis(mesh, f, values, level);
            EXPECT_LE(max_difference(values, mesh.positions, values.size()), tolerance)
                << "k " << k << " level " << level;
        }
    }
}

TEST(MapsWavelet, LazyAnalysisIsSubsampling) {
    const gp::SemiRegularMesh mesh = curved_remesh(4, 0.02);
    const std::uint32_t coarse = mesh.vertex_count[3];
    std::vector<glm::dvec3> lazy = mesh.positions, disk1 = mesh.positions;
    gp::wavelet_analysis(mesh, gp::wavelet_filters(mesh, -1), lazy, 3);
    gp::wavelet_analysis(mesh, gp::wavelet_filters(mesh, 1), disk1, 3);
    EXPECT_EQ(max_difference(lazy, mesh.positions, coarse), 0.0);
    EXPECT_GT(max_difference(disk1, mesh.positions, coarse), 1e-3);  // the update smooths
    std::vector<glm::dvec3> full = mesh.positions;
    gp::wavelet_analysis(mesh, gp::wavelet_filters(mesh, -1), full);
    EXPECT_EQ(max_difference(full, mesh.positions, mesh.vertex_count[0]), 0.0);
}

TEST(MapsWavelet, ALinearSubdivisionHasNoDetails) {
    // A non-uniform base (radii jittered) subdivided linearly: the surface lies in V^0.
    geo::Mesh base = geo::make_icosphere(1.0, 0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> radius(0.6, 1.4);
    for (glm::dvec3& p : base.positions) p *= radius(rng);
    gp::SemiRegularMesh mesh = gp::subdivide_base(base, 4);
    place_linearly(mesh, base);
    const double tolerance = 1e-12 * diagonal(mesh.positions);
    for (int k : kAllWavelets) {
        const gp::WaveletFilters f = gp::wavelet_filters(mesh, k);
        std::vector<glm::dvec3> values = mesh.positions;
        gp::wavelet_analysis(mesh, f, values);
        double detail = 0.0;
        for (std::size_t m = mesh.vertex_count[0]; m < values.size(); ++m)
            detail = std::max(detail, glm::length(values[m]));
        EXPECT_LE(detail, tolerance) << "k " << k;
        EXPECT_LE(max_difference(values, base.positions, base.vertex_count()), tolerance) << "k " << k;
        std::vector<glm::dvec3> one_down = mesh.positions;
        gp::wavelet_analysis(mesh, f, one_down, 3);
        EXPECT_LE(max_difference(one_down, mesh.positions, mesh.vertex_count[3]), tolerance) << "k " << k;
    }
}

TEST(MapsWavelet, OneLevelDownErrorFallsWithK) {
    const gp::SemiRegularMesh mesh = curved_remesh(4, 0.0);
    const std::uint32_t J = 4, coarse = mesh.vertex_count[J - 1];
    const Eigen::SparseMatrix<double> m = mass(mesh, J);
    std::map<int, double> error;
    for (int k : kAllWavelets) {
        const gp::WaveletFilters f = gp::wavelet_filters(mesh, k);
        std::vector<glm::dvec3> values = mesh.positions;
        gp::wavelet_analysis(mesh, f, values, J - 1);
        std::fill(values.begin() + coarse, values.end(), glm::dvec3(0.0));
        gp::wavelet_synthesis(mesh, f, values, J - 1);
        error[k] = std::sqrt(l2_squared(m, values, mesh.positions));
    }
    // The least-squares approximation in V^{J-1} bounds them all from below.
    std::vector<Eigen::Triplet<double>> p;
    for (std::uint32_t i = 0; i < coarse; ++i) p.emplace_back(i, i, 1.0);
    for (std::uint32_t v = coarse; v < mesh.vertex_count[J]; ++v) {
        const glm::uvec2 e = mesh.parents[v - mesh.vertex_count[0]];
        p.emplace_back(v, e.x, 0.5);
        p.emplace_back(v, e.y, 0.5);
    }
    Eigen::SparseMatrix<double> prolong(mesh.vertex_count[J], coarse);
    prolong.setFromTriplets(p.begin(), p.end());
    const Eigen::SparseMatrix<double> normal = prolong.transpose() * m * prolong;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
    std::vector<glm::dvec3> best(mesh.vertex_count[J]);
    for (int c = 0; c < 3; ++c) {
        Eigen::VectorXd fine(mesh.vertex_count[J]);
        for (std::uint32_t v = 0; v < mesh.vertex_count[J]; ++v) fine(v) = mesh.positions[v][c];
        const Eigen::VectorXd approx = prolong * solver.solve(prolong.transpose() * (m * fine));
        for (std::uint32_t v = 0; v < mesh.vertex_count[J]; ++v) best[v][c] = approx(v);
    }
    const double optimum = std::sqrt(l2_squared(m, best, mesh.positions));
    std::printf("one level down, L2 error: lazy %.6e, k=0 %.6e, k=1 %.6e, k=2 %.6e, least squares %.6e\n", error[-1],
                error[0], error[1], error[2], optimum);
    EXPECT_LT(error[0], 0.9 * error[-1]);
    EXPECT_LE(error[1], error[0]);
    EXPECT_LE(error[2], error[1]);
    EXPECT_GE(error[2], optimum * (1.0 - 1e-12));
}

TEST(MapsWavelet, KeepingMoreDetailsLowersTheError) {
    gp::SemiRegularMesh mesh = curved_remesh(4, 0.01);
    const gp::WaveletFilters f = gp::wavelet_filters(mesh, 1);
    std::vector<glm::dvec3> coefficients = mesh.positions;
    gp::wavelet_analysis(mesh, f, coefficients);
    const std::size_t details = coefficients.size() - mesh.vertex_count[0];
    const Eigen::SparseMatrix<double> m = mass(mesh, 4);
    double previous = 1e300;
    for (double fraction : {0.0, 0.02, 0.1, 0.3, 0.7, 1.0}) {
        std::vector<glm::dvec3> kept = coefficients;
        const std::size_t count = gp::keep_largest_details(mesh, kept, fraction);
        EXPECT_EQ(count, std::size_t(std::llround(fraction * double(details))));
        EXPECT_EQ(max_difference(kept, coefficients, mesh.vertex_count[0]), 0.0);
        std::size_t nonzero = 0;
        double smallest_kept = 1e300, largest_dropped = 0.0;
        for (std::uint32_t j = 0; j < 4; ++j)
            for (std::uint32_t v = mesh.vertex_count[j]; v < mesh.vertex_count[j + 1]; ++v) {
                const double size = glm::length(coefficients[v]) * std::ldexp(1.0, -int(j) - 1);
                if (kept[v] != glm::dvec3(0.0)) {
                    ++nonzero;
                    EXPECT_EQ(kept[v], coefficients[v]);
                    smallest_kept = std::min(smallest_kept, size);
                } else {
                    largest_dropped = std::max(largest_dropped, size);
                }
            }
        EXPECT_EQ(nonzero, count);
        EXPECT_LE(largest_dropped, smallest_kept);
        gp::wavelet_synthesis(mesh, f, kept);
        const double error = std::sqrt(l2_squared(m, kept, mesh.positions));
        EXPECT_LT(error, fraction == 1.0 ? 1e-12 : previous) << "fraction " << fraction;
        previous = error;
    }
    EXPECT_THROW(gp::keep_largest_details(mesh, coefficients, 1.5), geo::InputError);
}

TEST_F(MapsWaveletGpu, AnalysisAndSynthesisEqualTheCpu) {
    const gp::SemiRegularMesh mesh = curved_remesh(4, 0.02);
    const double tolerance = 1e-12 * diagonal(mesh.positions);
    for (int k : kAllWavelets) {
        const gp::WaveletFilters f = gp::wavelet_filters(mesh, k);
        gp::WaveletBuffers uploaded = gp::upload_wavelet_filters(ctx(), mesh, f);  // kept across calls
        for (std::uint32_t level : {0u, 2u}) {
            std::vector<glm::dvec3> cpu = mesh.positions;
            gp::wavelet_analysis(mesh, f, cpu, level);
            const std::vector<glm::dvec3> gpu = gp::wavelet_analysis_gpu(ctx(), mesh, f, mesh.positions, level);
            EXPECT_LE(max_difference(gpu, cpu, cpu.size()), tolerance) << "analysis k " << k << " level " << level;
            EXPECT_EQ(gp::wavelet_analysis_gpu(ctx(), mesh, uploaded, mesh.positions, level), gpu);
            // Synthesis of perturbed coefficients, so that it is not just undoing the analysis.
            std::vector<glm::dvec3> coefficients = cpu;
            for (std::size_t v = 0; v < coefficients.size(); v += 3) coefficients[v] *= 1.5;
            std::vector<glm::dvec3> back = coefficients;
            gp::wavelet_synthesis(mesh, f, back, level);
            const std::vector<glm::dvec3> gpu_back = gp::wavelet_synthesis_gpu(ctx(), mesh, f, coefficients, level);
            EXPECT_LE(max_difference(gpu_back, back, back.size()), tolerance)
                << "synthesis k " << k << " level " << level;
            EXPECT_EQ(gp::wavelet_synthesis_gpu(ctx(), mesh, uploaded, coefficients, level), gpu_back);
            EXPECT_GT(max_difference(back, mesh.positions, back.size()), 1e-2);
        }
    }
}

TEST_F(MapsWaveletGpu, MeshesPastTheTexelArraysAreReportedAsNotFitting) {
    const gp::SemiRegularMesh mesh = curved_remesh(2, 0.02);
    const gp::WaveletFilters f = gp::wavelet_filters(mesh, 1);
    ASSERT_EQ(gp::wavelets_fit_device(ctx(), mesh, f), ctx().device_info().shader_float64);
    // Six texels per vertex: one vertex more than the rows hold does not fit (counts alone, nothing
    // allocated).
    const std::size_t texels = std::size_t(ctx().device_info().max_image_dimension_2d) * kTexelArrayRowWidth;
    gp::SemiRegularMesh big = mesh;
    big.vertex_count.back() = std::uint32_t(texels / 6);
    EXPECT_EQ(gp::wavelets_fit_device(ctx(), big, f), ctx().device_info().shader_float64);
    big.vertex_count.back() += 1;
    EXPECT_FALSE(gp::wavelets_fit_device(ctx(), big, f));
}

TEST_F(MapsWaveletGpu, AnalysisAndSynthesisChainInOneGraph) {
    const gp::SemiRegularMesh mesh = curved_remesh(3, 0.02);
    gp::WaveletBuffers filters = gp::upload_wavelet_filters(ctx(), mesh, gp::wavelet_filters(mesh, 2));
    Buffer values = upload_buffer(ctx(), mesh.positions, "values");
    Graph g(ctx());
    BufferHandle h = g.import_buffer(values);
    h = gp::add_wavelet_analysis(g, h, mesh, filters);
    // Drop the finest details on the GPU, between the two transforms.
    const VkDeviceSize first = VkDeviceSize(mesh.vertex_count[2]) * sizeof(glm::dvec3);
    g.add_compute_pass(
        "drop finest details", [&](PassBuilder& b) { h = b.write(h, Access::TransferDst); },
        [=](Cmd& c) { c.fill(h, 0, first); });
    h = gp::add_wavelet_synthesis(g, h, mesh, filters);
    g.export_buffer(h, Access::TransferSrc);
    Plan plan = g.compile();
    plan.execute();
    const std::vector<glm::dvec3> gpu = ctx().download<glm::dvec3>(values);
    std::vector<glm::dvec3> cpu = mesh.positions;
    const gp::WaveletFilters f = gp::wavelet_filters(mesh, 2);
    gp::wavelet_analysis(mesh, f, cpu);
    std::fill(cpu.begin() + mesh.vertex_count[2], cpu.end(), glm::dvec3(0.0));
    gp::wavelet_synthesis(mesh, f, cpu);
    ASSERT_EQ(gpu.size(), cpu.size());
    EXPECT_LE(max_difference(gpu, cpu, cpu.size()), 1e-12 * diagonal(mesh.positions));
    EXPECT_GT(max_difference(gpu, mesh.positions, cpu.size()), 1e-3);
}

TEST_F(MapsWaveletGpu, TimesALevelFiveMesh) {
    // A 50-vertex base (the MAPS default size) subdivided five times: 49154 vertices.
    const geo::Mesh base = geo::make_uv_sphere(8, 7);
    gp::SemiRegularMesh mesh = gp::subdivide_base(base, 5);
    place_linearly(mesh, base);
    for (glm::dvec3& p : mesh.positions) p = glm::normalize(p);
    ASSERT_EQ(mesh.vertex_count.back(), 49154u);
    using clock = std::chrono::steady_clock;
    auto ms = [](clock::time_point a, clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    const auto t0 = clock::now();
    const gp::WaveletFilters f = gp::wavelet_filters(mesh, 1);
    const auto t1 = clock::now();
    std::vector<glm::dvec3> cpu = mesh.positions;
    gp::wavelet_analysis(mesh, f, cpu);
    gp::wavelet_synthesis(mesh, f, cpu);
    const auto t2 = clock::now();
    gp::WaveletBuffers filters = gp::upload_wavelet_filters(ctx(), mesh, f);
    Buffer values = upload_buffer(ctx(), mesh.positions, "values");
    Graph g(ctx());
    BufferHandle h = g.import_buffer(values);
    h = gp::add_wavelet_synthesis(g, gp::add_wavelet_analysis(g, h, mesh, filters), mesh, filters);
    g.export_buffer(h, Access::TransferSrc);
    Plan plan = g.compile();
    plan.execute();  // the first execution creates the pipelines
    const auto t3 = clock::now();
    plan.execute({.wait = true, .timestamps = ctx().device_info().timestamp_period_ns > 0.0});
    const auto t4 = clock::now();
    const double gpu_ms = ctx().device_info().timestamp_period_ns > 0.0 ? plan.total_gpu_ms() : 0.0;
    std::printf(
        "level 5, %u vertices, k = 1: filters %.1f ms; analysis + synthesis CPU %.2f ms, GPU %.2f ms wall "
        "(%.2f ms in passes; upload, compile and first run %.1f ms)\n",
        mesh.vertex_count.back(), ms(t0, t1), ms(t1, t2), ms(t3, t4), gpu_ms, ms(t2, t3));
    const std::vector<glm::dvec3> gpu = ctx().download<glm::dvec3>(values);
    EXPECT_LE(max_difference(gpu, mesh.positions, gpu.size()), 1e-12);
    EXPECT_LE(max_difference(cpu, mesh.positions, cpu.size()), 1e-12);
}

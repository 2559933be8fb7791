// MAPS base domain, tracking and remesh (spec sec. 2.9 items 1-4): every level an independent set
// removed from a closed manifold of the input's Euler characteristic, the z^a flattening rigid on a
// flat ring and scaled on a cone, the refill Delaunay, every original vertex tracked after every
// removal, remesh counts, remesh points on the original surface, the error falling with the level,
// the GPU evaluation against its CPU twin, and the refusals.
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/bvh.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/maps.h"
#include "maps/ring_flattening.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <set>

using namespace gimg;
namespace gp = gimg::passes;

namespace {

class MapsRemeshGpu : public gimg::test::GpuTest {};

// A sphere whose vertices are pushed around on it (so the connectivity is irregular in the metric).
geo::Mesh jittered_sphere(int level) {
    geo::Mesh m = geo::make_icosphere(1.0, level);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> d(-0.25, 0.25);
    const double edge = glm::distance(m.positions[m.triangles[0][0]], m.positions[m.triangles[0][1]]);
    for (auto& p : m.positions) p = glm::normalize(p + edge * glm::dvec3(d(rng), d(rng), d(rng)));
    return m;
}

std::vector<geo::Mesh> test_meshes() {
    std::vector<geo::Mesh> meshes{jittered_sphere(3), geo::make_torus(1.0, 0.35, 40, 16)};
    if (auto p = test::shared_mesh("eight.off")) meshes.push_back(geo::load_mesh(*p));
    return meshes;
}

long long euler(const geo::Mesh& m) {
    const geo::MeshInfo info = geo::analyze_topology(m);
    long long chi = 0;
    for (const auto& c : info.component_info) chi += c.euler_characteristic;
    return chi;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> edges_of(const std::vector<glm::uvec3>& faces) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> e;
    for (const auto& t : faces)
        for (int k = 0; k < 3; ++k) e.insert(std::minmax(t[k], t[(k + 1) % 3]));
    return e;
}

}  // namespace

TEST(MapsHierarchy, EveryLevelRemovesAnIndependentSetAndStaysAClosedManifold) {
    for (const geo::Mesh& mesh : test_meshes()) {
        gp::MapsOptions o;
        o.keep_levels = o.check_tracking = true;
        const gp::BaseDomain d = gp::build_base_domain(mesh, o);
        const long long chi = euler(mesh);
        ASSERT_GE(d.levels.size(), 3u);
        std::vector<glm::uvec3> previous = mesh.triangles;
        for (std::size_t l = 0; l < d.levels.size(); ++l) {
            const auto edges = edges_of(previous);
            const auto& removed = d.removed_sets[l];
            ASSERT_EQ(removed.size(), d.levels[l].removed);
            const std::set<std::uint32_t> set(removed.begin(), removed.end());
            for (const auto& [a, b] : edges) EXPECT_FALSE(set.count(a) && set.count(b)) << "level " << l;
            geo::Mesh level{mesh.positions, d.level_faces[l], {}, {}};
            const geo::MeshInfo info = geo::analyze_topology(level);
            EXPECT_TRUE(info.closed && info.manifold && info.oriented) << "level " << l;
            EXPECT_EQ(info.duplicate_faces, 0u);
            EXPECT_EQ(euler(level), chi) << "level " << l;
            EXPECT_EQ(mesh.vertex_count() - info.isolated_vertices, d.levels[l].vertices);
            for (const auto& t : d.level_faces[l])
                for (int k = 0; k < 3; ++k) EXPECT_FALSE(set.count(t[k]));
            previous = d.level_faces[l];
        }
        // A constant share removed per level: O(log N) levels.
        for (std::size_t l = 0; l + 1 < d.levels.size(); ++l)
            EXPECT_GT(d.levels[l].removed, (d.levels[l].vertices + d.levels[l].removed) / 20) << "level " << l;
        EXPECT_EQ(euler(d.base), chi);
        EXPECT_LE(d.base.vertex_count(), std::max<std::size_t>(50 * (1 + (2 - chi) / 2), 4));
    }
}

TEST(MapsHierarchy, EveryOriginalVertexMapsIntoTheBaseDomain) {
    const geo::Mesh mesh = jittered_sphere(3);
    const gp::BaseDomain d = gp::build_base_domain(mesh, {.base_vertices = 30});
    EXPECT_EQ(d.base.vertex_count(), 30u);
    ASSERT_EQ(d.param.size(), mesh.vertex_count());
    for (const gp::SurfacePoint& p : d.param) {
        ASSERT_LT(p.face, d.base.face_count());
        EXPECT_GE(std::min({p.bary.x, p.bary.y, p.bary.z}), 0.0);
        EXPECT_NEAR(p.bary.x + p.bary.y + p.bary.z, 1.0, 1e-12);
    }
    // Base vertices are identity (case 1): they sit at their own corner.
    for (std::uint32_t b = 0; b < d.base.vertex_count(); ++b) {
        const gp::SurfacePoint& p = d.param[d.original[b]];
        const glm::uvec3 t = d.base.triangles[p.face];
        for (int k = 0; k < 3; ++k) EXPECT_EQ(p.bary[k], t[k] == b ? 1.0 : 0.0);
        EXPECT_EQ(d.base.positions[b], mesh.positions[d.original[b]]);
    }
}

TEST(MapsFlattening, AFlatRingIsRigidAndAConeIsScaled) {
    // Six neighbours in the plane z = 0 around the origin, irregular.
    std::vector<glm::dvec3> p{{0, 0, 0}};
    const double angles[6] = {0.1, 1.2, 2.0, 3.3, 4.1, 5.3}, radii[6] = {1.0, 0.7, 1.3, 0.9, 1.1, 0.8};
    for (int k = 0; k < 6; ++k) p.push_back({radii[k] * std::cos(angles[k]), radii[k] * std::sin(angles[k]), 0.0});
    gp::Ring r;
    r.ring = {1, 2, 3, 4, 5, 6};
    ASSERT_TRUE(gp::flatten_ring(p, 0, r));
    // a = 1: every distance kept up to the chart's one scale (1 / longest radius).
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            EXPECT_NEAR(glm::distance(r.mu[std::size_t(i)], r.mu[std::size_t(j)]) * 1.3,
                        glm::distance(glm::dvec2(p[std::size_t(i + 1)]), glm::dvec2(p[std::size_t(j + 1)])), 1e-12);
    // A cone: the apex lifted, total angle below 2 pi, so a > 1 and radii go as r^a.
    p[0].z = 0.8;
    ASSERT_TRUE(gp::flatten_ring(p, 0, r));
    double total = 0.0;
    for (int k = 0; k < 6; ++k)
        total += gp::corner_angle(p[0], p[std::size_t(k + 1)], p[std::size_t(k + 2 > 6 ? 1 : k + 2)]);
    const double a = 2.0 * std::numbers::pi / total;
    ASSERT_GT(a, 1.1);
    double longest = 0.0;
    for (int k = 1; k <= 6; ++k) longest = std::max(longest, glm::distance(p[0], p[std::size_t(k)]));
    double turned = 0.0;
    for (int k = 0; k < 6; ++k) {
        EXPECT_NEAR(glm::length(r.mu[std::size_t(k)]),
                    std::pow(glm::distance(p[0], p[std::size_t(k + 1)]) / longest, a), 1e-12);
        const glm::dvec2 u = r.mu[std::size_t(k)], w = r.mu[std::size_t((k + 1) % 6)];
        turned += std::atan2(u.x * w.y - u.y * w.x, glm::dot(u, w));
    }
    EXPECT_NEAR(turned, 2.0 * std::numbers::pi, 1e-12);  // scaled angles sum to 2 pi
    // Polar radii: the same angles, the radii kept (up to the chart's scale).
    gp::Ring polar;
    polar.ring = r.ring;
    ASSERT_TRUE(gp::flatten_ring(p, 0, polar, true));
    for (int k = 0; k < 6; ++k) {
        EXPECT_NEAR(glm::length(polar.mu[std::size_t(k)]), glm::distance(p[0], p[std::size_t(k + 1)]) / longest, 1e-12);
        const glm::dvec2 u = polar.mu[std::size_t(k)], w = r.mu[std::size_t(k)];
        EXPECT_NEAR(u.x * w.y - u.y * w.x, 0.0, 1e-12);  // same direction as z^a's
    }
    // The cone guard: a tip whose total angle is below 2 pi / max_cone stays.
    p[0].z = 3.0;
    EXPECT_TRUE(gp::flatten_ring(p, 0, polar, true, 0.0));
    EXPECT_FALSE(gp::flatten_ring(p, 0, polar, true, 2.0));
}

TEST(MapsFlattening, TheRefillIsADelaunayTriangulationOfThePolygon) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> radius(0.5, 1.5), z(-0.3, 0.3);
    for (int trial = 0; trial < 50; ++trial) {
        const int k = 4 + trial % 9;
        std::vector<glm::dvec3> p{{0, 0, 0}};
        for (int i = 0; i < k; ++i) {
            const double a = 2.0 * std::numbers::pi * (i + 0.3 * std::sin(3.0 * i + trial)) / k;
            p.push_back({radius(rng) * std::cos(a), radius(rng) * std::sin(a), z(rng)});
        }
        gp::Ring r;
        for (int i = 1; i <= k; ++i) r.ring.push_back(std::uint32_t(i));
        if (!gp::flatten_ring(p, 0, r)) continue;
        ASSERT_TRUE(gp::triangulate_ring(r));
        ASSERT_EQ(r.triangles.size(), std::size_t(k - 2));
        double area = 0.0, polygon = 0.0;
        for (const auto& t : r.triangles) {
            const glm::dvec2 a = r.mu[t[0]], b = r.mu[t[1]], c = r.mu[t[2]];
            const double s = 0.5 * ((b - a).x * (c - a).y - (b - a).y * (c - a).x);
            EXPECT_GT(s, 0.0);
            area += s;
            // No ring point strictly inside a triangle's circumcircle that it can see: for a
            // polygon refill, the empty-circle test holds for the points across each diagonal,
            // and a convex ring has all of them.
            for (std::size_t q = 0; q < r.mu.size(); ++q) {
                if (q == t[0] || q == t[1] || q == t[2]) continue;
                const glm::dvec2 ad = a - r.mu[q], bd = b - r.mu[q], cd = c - r.mu[q];
                const double det = glm::dot(ad, ad) * (bd.x * cd.y - bd.y * cd.x) -
                                   glm::dot(bd, bd) * (ad.x * cd.y - ad.y * cd.x) +
                                   glm::dot(cd, cd) * (ad.x * bd.y - ad.y * bd.x);
                bool convex = true;
                for (std::size_t i = 0; i < r.mu.size(); ++i) {
                    const glm::dvec2 u = r.mu[(i + 1) % r.mu.size()] - r.mu[i],
                                     w = r.mu[(i + 2) % r.mu.size()] - r.mu[i];
                    convex = convex && u.x * w.y - u.y * w.x > 0.0;
                }
                if (convex) {
                    EXPECT_LE(det, 1e-9);
                }
            }
        }
        for (std::size_t i = 0; i < r.mu.size(); ++i) {
            const glm::dvec2 u = r.mu[i], w = r.mu[(i + 1) % r.mu.size()];
            polygon += 0.5 * (u.x * w.y - u.y * w.x);
        }
        EXPECT_NEAR(area, polygon, 1e-12);  // the triangles tile the polygon
    }
}

TEST(MapsRemesh, PointsLieOnTheOriginalAndTheErrorFallsWithTheLevel) {
    const geo::Mesh mesh = jittered_sphere(3);
    const gp::MapsRemesh r = gp::maps_remesh(nullptr, mesh, {}, 4);
    const std::size_t f0 = r.domain.base.face_count();
    for (std::uint32_t j = 0; j <= 4; ++j) EXPECT_EQ(r.remesh.faces[j].size(), f0 << (2 * j));
    EXPECT_EQ(r.map.unplaced, 0u);
    EXPECT_EQ(r.fallbacks, 0u);
    EXPECT_EQ(r.map.inverted, 0u);
    // Level 0 is the base domain itself.
    for (std::uint32_t v = 0; v < r.remesh.vertex_count[0]; ++v)
        EXPECT_EQ(r.remesh.positions[v], r.domain.base.positions[v]);
    const geo::TriangleBvh bvh(mesh);
    const double diagonal = mesh.bounds().diagonal();
    double worst = 0.0;
    for (const glm::dvec3& p : r.remesh.positions) worst = std::max(worst, bvh.closest_point(p).distance);
    EXPECT_LE(worst, 1e-9 * diagonal);
    // Within the sphere mesh's chordal error of the unit sphere.
    for (const glm::dvec3& p : r.remesh.positions) {
        EXPECT_LE(glm::length(p), 1.0 + 1e-9);
        EXPECT_GE(glm::length(p), 0.97);
    }
    geo::SurfaceDistanceOptions so;
    so.sampling.sample_count = 50000;
    double previous = 1e300;
    for (std::uint32_t j = 1; j <= 4; ++j) {
        const geo::SurfaceDistance d = geo::surface_distance(mesh, r.remesh.level_mesh(j), so);
        EXPECT_LT(d.symmetric.rms, previous) << "level " << j;
        previous = d.symmetric.rms;
    }
    EXPECT_LT(previous / diagonal, 2e-3);
}

// The goal on the genus-0 mesh that missed it with a 50-vertex base: cow's horns, ears
// and legs are thinner than those base triangles, and level 5 stayed at 1.19e-3 of the diagonal.
TEST(MapsSharedMeshes, CowLevelFiveIsWithinAThousandthOfTheDiagonal) {
    GIMG_REQUIRE_SHARED_MESH(cow, "cow.off");
    const geo::Mesh mesh = geo::load_mesh(cow);
    const gp::MapsRemesh r = gp::maps_remesh(nullptr, mesh, {}, 5);
    EXPECT_EQ(r.domain.base.vertex_count(), mesh.vertex_count() / 20);  // the default: a twentieth
    geo::SurfaceDistanceOptions so;
    so.sampling.sample_count = 300000;
    const double rms = geo::surface_distance(mesh, r.remesh.level_mesh(5), so).symmetric.rms;
    EXPECT_LT(rms / mesh.bounds().diagonal(), 1e-3);
    gp::MapsOptions fifty;
    fifty.base_vertices = 50;
    const gp::MapsRemesh coarse = gp::maps_remesh(nullptr, mesh, fifty, 5);
    EXPECT_GT(geo::surface_distance(mesh, coarse.remesh.level_mesh(5), so).symmetric.rms, 2.0 * rms);
}

TEST(MapsRemesh, TheImagesCoverEveryBaseTriangleWithoutInversion) {
    // Bijectivity of Pi as far as the charts allow: no image is inverted, and random points of every
    // base triangle each lie strictly inside the image of at least one original triangle (searched
    // in the triangle's chart and its corners' charts). Where two base vertices' charts disagree
    // near a base edge, a point can lie in two images; their share is printed, not asserted.
    const geo::Mesh mesh = jittered_sphere(3);
    const gp::BaseDomain d = gp::build_base_domain(mesh);
    const gp::InverseMap m = gp::build_inverse_map(mesh, d);
    EXPECT_EQ(m.inverted, 0u);
    EXPECT_EQ(m.unplaced, 0u);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::size_t once = 0, none = 0, samples = 0;
    for (std::uint32_t f = 0; f < d.base.face_count(); ++f)
        for (int s = 0; s < 200; ++s) {
            double a = u(rng), b = u(rng);
            if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
            const glm::dvec3 q(1.0 - a - b, a, b);
            std::set<std::uint32_t> holders;
            for (int c = 0; c < 4; ++c) {
                const std::uint32_t chart = m.face_charts[8 * f + std::uint32_t(c)];
                glm::dvec2 x(q.y, q.z);
                if (c > 0) {
                    const glm::dvec2* k = &m.corner_coords[9 * std::size_t(f) + 3 * std::size_t(c - 1)];
                    x = q.x * k[0] + q.y * k[1] + q.z * k[2];
                }
                const glm::uvec4 grid = m.chart_grid[chart];
                for (std::uint32_t i = m.cell_offsets[grid.z]; i < m.cell_offsets[grid.z + grid.x * grid.y]; ++i) {
                    const std::uint32_t t = m.cell_items[i];
                    const glm::dvec3 w = gp::barycentric_2d(x, m.triangle_coords[3 * t], m.triangle_coords[3 * t + 1],
                                                            m.triangle_coords[3 * t + 2]);
                    if (std::min({w.x, w.y, w.z}) > 1e-9) holders.insert(m.triangle_face[t]);
                }
            }
            ++samples;
            once += holders.size() == 1;
            none += holders.empty();
        }
    EXPECT_EQ(none, 0u) << "points of the base domain in no original triangle's image";
    std::printf("%zu of %zu samples in exactly one image, %zu in two or more (charts disagreeing)\n", once, samples,
                samples - once - none);
}

TEST(MapsRemesh, AMeshThatIsItsOwnBaseRemeshesToItsLinearSubdivision) {
    // A tetrahedron (under the base size, and valence 3, where a vertex chart holds the whole
    // surface): every remesh point is the flat point of its base triangle, those on base edges too.
    geo::Mesh tetra;
    tetra.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const gp::MapsRemesh r = gp::maps_remesh(nullptr, tetra, {}, 3);  // the CPU twin
    ASSERT_EQ(r.domain.levels.size(), 0u);
    EXPECT_EQ(r.fallbacks, 0u);
    for (std::size_t i = 0; i < r.remesh.positions.size(); ++i) {
        const gp::SurfacePoint& q = r.remesh.base_point[i];
        const glm::uvec3 t = r.domain.base.triangles[q.face];
        const glm::dvec3 flat = q.bary.x * r.domain.base.positions[t[0]] + q.bary.y * r.domain.base.positions[t[1]] +
                                q.bary.z * r.domain.base.positions[t[2]];
        EXPECT_LE(glm::distance(r.remesh.positions[i], flat), 1e-12) << "point " << i;
    }
}

TEST(MapsRemesh, HigherGenusKeepsItsTopology) {
    const geo::Mesh torus = geo::make_torus(1.0, 0.35, 80, 32);
    const gp::MapsRemesh r = gp::maps_remesh(nullptr, torus, {}, 3);
    EXPECT_EQ(r.fallbacks, 0u);
    EXPECT_EQ(r.map.unplaced, 0u);
    for (std::uint32_t j = 0; j <= 3; ++j) {
        const geo::MeshInfo info = geo::analyze_topology(r.remesh.level_mesh(j));
        EXPECT_TRUE(info.closed && info.manifold && info.oriented);
        ASSERT_EQ(info.component_info.size(), 1u);
        EXPECT_EQ(info.component_info[0].genus.value_or(-1), 1);
    }
}

TEST(MapsRemesh, RefusesWhatIsNotAClosedManifold) {
    EXPECT_THROW(gp::build_base_domain(geo::make_grid(4, 4)), geo::InputError);
    geo::Mesh fin = geo::make_icosphere(1.0, 1);
    fin.positions.push_back({3, 3, 3});
    fin.triangles.push_back({fin.triangles[0][0], fin.triangles[0][1], std::uint32_t(fin.positions.size() - 1)});
    EXPECT_THROW(gp::build_base_domain(fin), geo::InputError);
    geo::Mesh flipped = geo::make_icosphere(1.0, 1);
    std::swap(flipped.triangles[0][0], flipped.triangles[0][1]);
    EXPECT_THROW(gp::build_base_domain(flipped), geo::InputError);
    EXPECT_THROW(gp::build_base_domain(geo::make_icosphere(1.0, 1), {.lambda = 2.0}), geo::InputError);
}

TEST_F(MapsRemeshGpu, TheGpuEvaluationEqualsTheCpuTwin) {
    std::vector<geo::Mesh> meshes{jittered_sphere(3), geo::make_torus(1.0, 0.35, 40, 16)};
    if (auto p = test::shared_mesh("bunny_small.obj")) meshes.push_back(geo::load_mesh(*p));
    for (const geo::Mesh& mesh : meshes) {
        const gp::BaseDomain d = gp::build_base_domain(mesh);
        const gp::InverseMap map = gp::build_inverse_map(mesh, d);
        const gp::SemiRegularMesh s = gp::subdivide_base(d.base, 4);
        std::size_t cpu_missed = 0, gpu_missed = 0;
        const auto cpu = gp::evaluate_inverse_map(mesh, map, s.base_point, &cpu_missed);
        const auto gpu = gp::evaluate_inverse_map_gpu(ctx(), mesh, map, s.base_point, &gpu_missed);
        ASSERT_EQ(cpu.size(), gpu.size());
        double worst = 0.0;
        for (std::size_t i = 0; i < cpu.size(); ++i) worst = std::max(worst, glm::distance(cpu[i], gpu[i]));
        EXPECT_LE(worst, 1e-12 * mesh.bounds().diagonal());
        EXPECT_EQ(cpu_missed, gpu_missed);
    }
}

#include "flat_box_rays.h"
#include "gimg/geometry/bvh.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/geometry/triangle_queries.h"

#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <random>

using namespace gimg::geo;

namespace {

ClosestPointResult brute_force_closest(const Mesh& m, const glm::dvec3& p) {
    ClosestPointResult best;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::uint32_t f = 0; f < m.face_count(); ++f) {
        const auto& t = m.triangles[f];
        const TrianglePoint tp = closest_point_on_triangle(p, m.positions[t.x], m.positions[t.y], m.positions[t.z]);
        if (tp.distance_squared < best_d2) {  // strict: the lowest face index wins ties
            best_d2 = tp.distance_squared;
            best.face = f;
            best.point = tp.point;
            best.barycentric = tp.barycentric;
        }
    }
    best.distance = std::sqrt(best_d2);
    return best;
}

std::vector<RayHit> brute_force_hits(const Mesh& m, const Ray& ray) {
    std::vector<RayHit> hits;
    for (std::uint32_t f = 0; f < m.face_count(); ++f) {
        const auto& t = m.triangles[f];
        TriangleHit h;
        if (intersect_ray_triangle(ray, m.positions[t.x], m.positions[t.y], m.positions[t.z], h))
            hits.push_back({h.t, f, h.barycentric});
    }
    std::stable_sort(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) { return a.t < b.t; });
    return hits;
}

// A sphere plus a soup of random triangles, slivers, collinear and repeated-corner faces and a
// duplicated face, so ties and degenerate cases are exercised.
Mesh awkward_mesh() {
    Mesh m = gimg::geo::make_icosphere(1.0, 3);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int i = 0; i < 200; ++i) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        const glm::dvec3 a(u(rng), u(rng), u(rng));
        glm::dvec3 b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
        if (i % 5 == 1) c = a + 0.37 * (b - a);  // collinear
        if (i % 5 == 2) c = b;                   // two corners equal
        if (i % 5 == 3) c = a + 1e-9 * (c - a);  // sliver
        m.positions.insert(m.positions.end(), {a, b, c});
        m.triangles.push_back({base, base + 1, base + 2});
    }
    m.triangles.push_back(m.triangles[5]);  // exact duplicate: a guaranteed tie
    m.triangles.push_back({3, 3, 3});       // a point
    return m;
}

}  // namespace

TEST(TriangleQueries, ClosestPointRegions) {
    const glm::dvec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
    auto q = closest_point_on_triangle({0.5, 0.5, 3}, a, b, c);  // above the face
    EXPECT_DOUBLE_EQ(q.distance_squared, 9.0);
    EXPECT_EQ(q.point, glm::dvec3(0.5, 0.5, 0));
    EXPECT_NEAR(glm::length(q.barycentric - glm::dvec3(0.5, 0.25, 0.25)), 0.0, 1e-15);
    q = closest_point_on_triangle({-1, -1, 1}, a, b, c);  // beyond corner a
    EXPECT_EQ(q.point, a);
    EXPECT_DOUBLE_EQ(q.distance_squared, 3.0);
    q = closest_point_on_triangle({1, -2, 0}, a, b, c);  // beyond edge ab
    EXPECT_EQ(q.point, glm::dvec3(1, 0, 0));
    EXPECT_DOUBLE_EQ(q.distance_squared, 4.0);
    q = closest_point_on_triangle({2, 2, 0}, a, b, c);  // beyond edge bc
    EXPECT_NEAR(glm::length(q.point - glm::dvec3(1, 1, 0)), 0.0, 1e-15);
    EXPECT_NEAR(q.distance_squared, 2.0, 1e-15);
    // Degenerate (collinear) triangle: the closest point on its segment.
    q = closest_point_on_triangle({1, 1, 0}, a, b, {1, 0, 0});
    EXPECT_EQ(q.point, glm::dvec3(1, 0, 0));
    EXPECT_DOUBLE_EQ(q.distance_squared, 1.0);
}

TEST(TriangleQueries, RayTriangle) {
    const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    TriangleHit h;
    ASSERT_TRUE(intersect_ray_triangle({{0.25, 0.25, 2}, {0, 0, -2}}, a, b, c, h));
    EXPECT_DOUBLE_EQ(h.t, 1.0);
    EXPECT_NEAR(glm::length(h.barycentric - glm::dvec3(0.5, 0.25, 0.25)), 0.0, 1e-15);
    EXPECT_TRUE(intersect_ray_triangle({{0.25, 0.25, -2}, {0, 0, 1}}, a, b, c, h));             // back side
    EXPECT_FALSE(intersect_ray_triangle({{0.75, 0.75, 2}, {0, 0, -1}}, a, b, c, h));            // outside
    EXPECT_FALSE(intersect_ray_triangle({{0.25, 0.25, 2}, {0, 0, 1}}, a, b, c, h));             // behind
    EXPECT_FALSE(intersect_ray_triangle({{0.25, 0.25, 2}, {0, 0, -1}, 0.0, 1.5}, a, b, c, h));  // t range
    EXPECT_TRUE(intersect_ray_triangle({{0.5, 0.5, 1}, {0, 0, -1}}, a, b, c, h));               // on edge bc
    EXPECT_FALSE(intersect_ray_triangle({{-1, 0.5, 0}, {1, 0, 0}}, a, b, c, h));                // in plane
}

TEST(Bvh, ClosestPointEqualsBruteForce) {
    const Mesh m = awkward_mesh();
    const TriangleBvh bvh(m);
    EXPECT_EQ(bvh.face_count(), m.face_count());
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    std::uint32_t hint = 0;
    for (int i = 0; i < 3000; ++i) {
        // Mix of free points and points exactly on faces (distance 0, many ties at shared edges).
        glm::dvec3 p(u(rng), u(rng), u(rng));
        if (i % 3 == 0) p = m.positions[m.triangles[i % m.face_count()].x];
        const ClosestPointResult expected = brute_force_closest(m, p);
        const ClosestPointResult got = bvh.closest_point(p);
        ASSERT_TRUE(got.found());
        EXPECT_NEAR(got.distance, expected.distance, 1e-12) << "query " << i;
        EXPECT_EQ(got.face, expected.face) << "query " << i;
        EXPECT_EQ(got.point, expected.point);
        // The hint only seeds the search: same answer from any starting face.
        const ClosestPointResult hinted = bvh.closest_point(p, std::numeric_limits<double>::infinity(), hint);
        EXPECT_EQ(hinted.face, expected.face);
        EXPECT_EQ(hinted.distance, got.distance);
        hint = (hint * 7 + 13) % static_cast<std::uint32_t>(m.face_count());
    }
    // A search radius below the true distance finds nothing; at it, finds the face.
    const glm::dvec3 far(4, 0, 0);
    const ClosestPointResult exact = bvh.closest_point(far);
    EXPECT_FALSE(bvh.closest_point(far, exact.distance * (1 - 1e-9)).found());
    EXPECT_EQ(bvh.closest_point(far, exact.distance).face, exact.face);
}

TEST(Bvh, ClosestPointOnSphereIsRadial) {
    const Mesh s = gimg::geo::make_icosphere(1.0, 4);
    const TriangleBvh bvh(s);
    // Points far outside: distance between |p| - 1 and |p| - (1 - sag), sag < 1e-3 at level 4.
    for (double r : {1.5, 3.0, 10.0}) {
        const ClosestPointResult q = bvh.closest_point({r * 0.6, r * 0.8, 0.0});
        EXPECT_GE(q.distance, r - 1.0 - 1e-12);
        EXPECT_LE(q.distance, r - 1.0 + 1e-3);
    }
}

TEST(Bvh, RayQueriesEqualBruteForce) {
    const Mesh m = awkward_mesh();
    const TriangleBvh bvh(m);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::size_t hit_count = 0;
    for (int i = 0; i < 3000; ++i) {
        Ray ray;
        ray.origin = 3.0 * glm::dvec3(u(rng), u(rng), u(rng));
        ray.direction = glm::dvec3(u(rng), u(rng), u(rng)) - 0.3 * ray.origin;
        if (i % 4 == 0) ray.direction = {0, 0, u(rng) < 0 ? -1.0 : 1.0};  // axis-parallel slabs
        if (i % 7 == 0) {  // in the z = 0 plane, which holds icosphere vertices and edges
            ray.origin.z = 0.0;
            ray.direction = {1, 0, 0};
        }
        if (i % 5 == 0) {
            ray.t_min = 0.5;
            ray.t_max = 2.0;
        }
        const std::vector<RayHit> expected = brute_force_hits(m, ray);
        const auto nearest = bvh.intersect_nearest(ray);
        ASSERT_EQ(nearest.has_value(), !expected.empty()) << "ray " << i;
        EXPECT_EQ(bvh.intersect_any(ray), !expected.empty());
        const std::vector<RayHit> all = bvh.intersect_all(ray);
        ASSERT_EQ(all.size(), expected.size()) << "ray " << i;
        std::vector<RayHit> sorted = expected;
        std::sort(sorted.begin(), sorted.end(),
                  [](const RayHit& a, const RayHit& b) { return a.t != b.t ? a.t < b.t : a.face < b.face; });
        for (std::size_t k = 0; k < all.size(); ++k) {
            EXPECT_EQ(all[k].t, sorted[k].t);
            EXPECT_EQ(all[k].face, sorted[k].face);
        }
        if (!expected.empty()) {
            ++hit_count;
            EXPECT_EQ(nearest->t, sorted[0].t);
            EXPECT_EQ(nearest->face, sorted[0].face);
            EXPECT_EQ(nearest->barycentric, sorted[0].barycentric);
        }
    }
    EXPECT_GT(hit_count, 500u);  // the test exercised hits (887 of 3000 rays), not just misses
}

TEST(Bvh, RaysNearlyParallelToFlatBoxesEqualBruteForce) {
    // A box's faces have flat boxes (flat_box_rays.h): a box test that rounds could lose a hit the
    // triangle test finds on an edge (the slab test once did, for components of 1e-31 and 1e-20).
    Mesh m = gimg::geo::make_box({2.0, 1.0, 0.5}, 6);
    for (int far = 0; far < 2; ++far) {
        if (far) {  // far from the origin, where float boxes are coarse
            for (glm::dvec3& p : m.positions) p += glm::dvec3(1000.0, -2000.0, 500.0);
        }
        const TriangleBvh bvh(m);
        std::size_t hit_count = 0;
        for (const bool front : {false, true})
            for (const Ray& ray : gimg::test::flat_box_rays(m, front)) {
                const std::vector<RayHit> expected = brute_force_hits(m, ray);
                ASSERT_EQ(bvh.intersect_all(ray).size(), expected.size());
                const auto nearest = bvh.intersect_nearest(ray);
                ASSERT_EQ(nearest.has_value(), !expected.empty());
                if (expected.empty()) continue;
                ++hit_count;
                std::uint32_t face = expected[0].face;  // stable: the lowest face at the least t
                for (const RayHit& h : expected)
                    if (h.t == expected[0].t) face = std::min(face, h.face);
                EXPECT_EQ(nearest->t, expected[0].t);
                EXPECT_EQ(nearest->face, face);
            }
        EXPECT_GT(hit_count, 1000u);
    }
}

TEST(Bvh, RayThroughSphereCrossesTwice) {
    const TriangleBvh bvh(gimg::geo::make_icosphere(2.0, 4));
    const auto hits = bvh.intersect_all({{0.1, 0.2, -10}, {0, 0, 1}});
    ASSERT_EQ(hits.size(), 2u);
    EXPECT_NEAR(hits[0].t, 10 - std::sqrt(4 - 0.05), 2e-3);
    EXPECT_NEAR(hits[1].t, 10 + std::sqrt(4 - 0.05), 2e-3);
}

TEST(Bvh, LayoutIsIndependentOfThreadCount) {
    BvhBuildOptions one;
    one.threads = 1;
    // The tree `mesh` gets on 2, 3, 4 and 8 threads is the one it gets on 1. A subtree gets a thread
    // whenever one is free, so which thread builds what changes from run to run; the tree may not.
    auto expect_the_serial_tree = [](const Mesh& mesh, const TriangleBvh& serial) {
        for (unsigned threads : {2u, 3u, 4u, 8u}) {
            BvhBuildOptions many;
            many.threads = threads;
            const TriangleBvh b(mesh, many);
            ASSERT_EQ(serial.nodes().size(), b.nodes().size());
            EXPECT_EQ(serial.face_order(), b.face_order());
            for (std::size_t i = 0; i < b.nodes().size(); ++i) {
                const BvhNode &x = serial.nodes()[i], &y = b.nodes()[i];
                ASSERT_EQ(x.first, y.first) << "node " << i << ", " << threads << " threads";
                ASSERT_EQ(x.count, y.count);
                ASSERT_EQ(x.bounds_min, y.bounds_min);
                ASSERT_EQ(x.bounds_max, y.bounds_max);
            }
        }
    };
    // ~160K faces: many subtrees above the threshold, handed out as threads come free.
    const Mesh m = gimg::geo::make_uv_sphere(400, 200);
    const TriangleBvh a(m, one);
    expect_the_serial_tree(m, a);
    // ~6K faces: a small mesh's two halves still get a thread each.
    const Mesh small = gimg::geo::make_uv_sphere(80, 40);
    expect_the_serial_tree(small, TriangleBvh(small, one));
    // Sibling pairs start at even indices (one cache line each on the 64-byte aligned array).
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.nodes().data()) % 64, 0u);
    for (std::size_t i = 0; i < a.nodes().size(); ++i) {
        if (i != 1 && !a.nodes()[i].is_leaf()) {  // node 1 is padding
            EXPECT_EQ(a.nodes()[i].first % 2, 0u);
        }
    }
    // Every face sits in exactly one leaf, within its leaf's box.
    std::vector<int> seen(m.face_count(), 0);
    for (const BvhNode& n : a.nodes()) {
        if (!n.is_leaf()) continue;
        EXPECT_LE(n.count, 4u);
        for (std::uint32_t s = n.first; s < n.first + n.count; ++s) {
            const std::uint32_t f = a.face_order()[s];
            ++seen[f];
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 p = m.positions[m.triangles[f][k]];
                EXPECT_TRUE(glm::all(glm::lessThanEqual(glm::dvec3(n.bounds_min), p)) &&
                            glm::all(glm::lessThanEqual(p, glm::dvec3(n.bounds_max))));
            }
        }
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), long(m.face_count()));
}

#ifdef __linux__
// The VmFlags of the mapping holding `address` (/proc/self/smaps), empty where none does.
std::string vm_flags_at(const void* address) {
    std::ifstream smaps("/proc/self/smaps");
    const auto at = reinterpret_cast<std::uintptr_t>(address);
    bool inside = false;
    for (std::string line; std::getline(smaps, line);) {
        unsigned long long begin = 0, end = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> begin >> dash >> end && dash == '-' && line.find(':') > line.find(' ')) {
            inside = begin <= at && at < end;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return {};
}
#endif

TEST(Bvh, ItsLargeArraysAskForHugePages) {
#ifndef __linux__
    GTEST_SKIP() << "huge-page advice is for Linux";
#else
    if (!std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled"))
        GTEST_SKIP() << "this kernel has no transparent huge pages";
    // A build's arrays of 4 MiB and more (1.2M faces: 21,000 first touches of 4 KB pages without).
    std::vector<char, UninitializedAllocator<char>> triangles(16u << 20);
    BvhNodeArray nodes;
    nodes.reserve((16u << 20) / sizeof(BvhNode));
    EXPECT_NE(vm_flags_at(triangles.data() + (8u << 20)).find(" hg"), std::string::npos)
        << vm_flags_at(triangles.data() + (8u << 20));
    EXPECT_NE(vm_flags_at(reinterpret_cast<const char*>(nodes.data()) + (8u << 20)).find(" hg"), std::string::npos);
    // An allocation under 4 MiB gets no advice.
    std::vector<char, UninitializedAllocator<char>> small(1u << 20);
    EXPECT_EQ(vm_flags_at(small.data()).find(" hg"), std::string::npos) << vm_flags_at(small.data());
#endif
}

TEST(Bvh, EmptyMeshAnswersNothing) {
    const TriangleBvh bvh{Mesh{}};
    EXPECT_TRUE(bvh.empty());
    EXPECT_FALSE(bvh.closest_point({0, 0, 0}).found());
    EXPECT_FALSE(bvh.intersect_nearest({}).has_value());
    EXPECT_FALSE(bvh.intersect_any({}));
}

TEST(ParallelFor, EveryChunkOnceAndErrorsPropagate) {
    std::vector<int> hits(1000, 0);
    std::vector<int> chunk_seen(chunk_count(1000, 64), 0);
    parallel_for_chunks(
        1000, 64,
        [&](std::size_t chunk, std::size_t begin, std::size_t end) {
            ++chunk_seen[chunk];
            EXPECT_EQ(begin, chunk * 64);
            for (std::size_t i = begin; i < end; ++i) ++hits[i];
        },
        3);
    EXPECT_EQ(std::count(hits.begin(), hits.end(), 1), 1000);
    EXPECT_EQ(std::count(chunk_seen.begin(), chunk_seen.end(), 1), long(chunk_seen.size()));
    EXPECT_THROW(parallel_for_chunks(
                     100, 1,
                     [](std::size_t c, std::size_t, std::size_t) {
                         if (c == 42) throw std::runtime_error("boom");
                     },
                     2),
                 std::runtime_error);
}

TEST(Bvh, CopiesOfATriangleAnswerAsTheLowestFaceAndIntersectAllReportsEach) {
    // awkward_mesh plus 3000 copies of its face 7 (corners in rotated order) and 3000 of face 11:
    // queries must answer as the brute force does (ties to the lowest face index), and the copies
    // stay out of the tree.
    Mesh m = awkward_mesh();
    const std::size_t original = m.face_count();
    for (int k = 0; k < 3000; ++k) {
        const glm::uvec3 a = m.triangles[7], b = m.triangles[11];
        m.triangles.push_back(k % 2 ? glm::uvec3(a.y, a.z, a.x) : a);
        m.triangles.push_back(k % 3 ? glm::uvec3(b.z, b.x, b.y) : b);
    }
    const TriangleBvh bvh(m);
    EXPECT_EQ(bvh.face_count(), m.face_count());
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    for (int i = 0; i < 300; ++i) {
        glm::dvec3 p(u(rng), u(rng), u(rng));
        if (i % 2 == 0) p = (m.positions[m.triangles[7].x] + m.positions[m.triangles[7].y]) * 0.5;
        const ClosestPointResult expected = brute_force_closest(m, p);
        const ClosestPointResult got = bvh.closest_point(p, std::numeric_limits<double>::infinity(),
                                                         std::uint32_t(original + i));  // a copy as the hint
        EXPECT_EQ(got.face, expected.face) << "query " << i;
        EXPECT_EQ(got.distance, expected.distance);
    }
    // A ray through face 7's centroid crosses face 7 and its 3000 copies at one t.
    const glm::uvec3 t7 = m.triangles[7];
    const glm::dvec3 c = (m.positions[t7.x] + m.positions[t7.y] + m.positions[t7.z]) / 3.0;
    const glm::dvec3 n =
        glm::normalize(glm::cross(m.positions[t7.y] - m.positions[t7.x], m.positions[t7.z] - m.positions[t7.x]));
    const Ray ray{c + 5.0 * n, -n};
    const std::vector<RayHit> expected = brute_force_hits(m, ray);
    const std::vector<RayHit> all = bvh.intersect_all(ray);
    ASSERT_EQ(all.size(), expected.size());
    EXPECT_GE(all.size(), 3001u);
    const auto nearest = bvh.intersect_nearest(ray);
    ASSERT_TRUE(nearest.has_value());
    std::vector<RayHit> sorted = expected;
    std::sort(sorted.begin(), sorted.end(),
              [](const RayHit& a, const RayHit& b) { return a.t != b.t ? a.t < b.t : a.face < b.face; });
    EXPECT_EQ(nearest->face, sorted[0].face);
    for (std::size_t k = 0; k < all.size(); ++k) EXPECT_EQ(all[k].face, sorted[k].face);
}

TEST(Bvh, TheLayoutIsTheTreesNodesAndOrderAndNamesTheKeptFaceOfEachCopy) {
    // awkward_mesh plus 40 copies of its face 7, some with rotated corners.
    Mesh m = awkward_mesh();
    const std::size_t original = m.face_count();
    for (int k = 0; k < 40; ++k) {
        const glm::uvec3 a = m.triangles[7];
        m.triangles.push_back(k % 2 ? glm::uvec3(a.z, a.x, a.y) : a);
    }
    const BvhLayout layout = build_bvh_layout(m);
    const TriangleBvh bvh(m);
    ASSERT_EQ(layout.nodes.size(), bvh.nodes().size());
    EXPECT_EQ(std::memcmp(layout.nodes.data(), bvh.nodes().data(), layout.nodes.size() * sizeof(BvhNode)), 0);
    EXPECT_EQ(layout.face_order, bvh.face_order());
    EXPECT_EQ(bvh_extent(layout.nodes), bvh.extent());
    // Every face appears once in the order; a copy answers by the lowest face with its corners.
    std::vector<std::uint32_t> seen(m.face_count(), 0);
    for (std::uint32_t f : layout.face_order) ++seen[f];
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1u), std::ptrdiff_t(m.face_count()));
    ASSERT_EQ(layout.kept_face.size(), m.face_count());
    for (std::size_t f = original; f < m.face_count(); ++f) EXPECT_EQ(layout.kept_face[f], 7u) << f;
    // awkward_mesh's own faces answer for themselves, but for its one duplicate (of face 5), which
    // may share a leaf with face 5 or be left out for it.
    for (std::size_t f = 0; f < original; ++f)
        if (f != original - 2) {
            EXPECT_EQ(layout.kept_face[f], f);
        }
    EXPECT_TRUE(layout.kept_face[original - 2] == original - 2 || layout.kept_face[original - 2] == 5u);
    // No leaf names a copy's slot.
    std::vector<std::uint8_t> in_leaf(m.face_count(), 0);
    for (const BvhNode& nd : layout.nodes)
        if (nd.is_leaf())
            for (std::uint32_t s = nd.first; s < nd.first + nd.count; ++s) in_leaf[layout.face_order[s]] = 1;
    for (std::size_t f = 0; f < m.face_count(); ++f) EXPECT_EQ(in_leaf[f] != 0, layout.kept_face[f] == f) << f;
}

TEST(Bvh, CrossingsCountAnEdgeOrACornerOnce) {
    const Mesh m = gimg::geo::make_icosphere(1.0, 0);
    const TriangleBvh bvh(m);
    for (const glm::dvec3& p : m.positions) {  // through a corner (five faces meet) and out again
        Ray ray{3.0 * p, -p};
        EXPECT_EQ(bvh.crossings(ray), 2u);
        ray.t_max = 2.5;  // stops inside
        EXPECT_EQ(bvh.crossings(ray), 1u);
    }
    const glm::uvec3 t = m.triangles[0];
    const glm::dvec3 edge = 0.5 * (m.positions[t.x] + m.positions[t.y]);  // through an edge
    EXPECT_EQ(bvh.crossings({3.0 * edge, -edge}), 2u);
}

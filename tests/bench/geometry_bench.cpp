// Google Benchmark cases for the CPU geometry core on procedural spheres: BVH build and
// closest-point throughput on ~1M triangles, and `compare` (surface distance, 1M samples each
// way) against a 50K-triangle sphere. Run with ./run bench or build/tests/bench/gimg_geometry_bench.
#include "gimg/geometry/bvh.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/geometry/surface_distance.h"

#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include <benchmark/benchmark.h>

#include <random>

using namespace gimg::geo;

namespace {

// 2 * 1000 * 499 = 998,000 triangles.
const Mesh& million_triangle_sphere() {
    static const Mesh m = gimg::geo::make_uv_sphere(1000, 500, 1.0);
    return m;
}

// 2 * 250 * 100 = 50,000 triangles.
const Mesh& fifty_k_sphere(double radius) {
    static const Mesh a = gimg::geo::make_uv_sphere(250, 101, 1.0);
    static const Mesh b = gimg::geo::make_uv_sphere(250, 101, 1.05);
    return radius == 1.0 ? a : b;
}

void BM_BvhBuild(benchmark::State& state) {
    const Mesh& m = million_triangle_sphere();
    BvhBuildOptions o;
    o.threads = static_cast<unsigned>(state.range(0));
    for (auto _ : state) {
        TriangleBvh bvh(m, o);
        benchmark::DoNotOptimize(bvh.nodes().data());
    }
    state.counters["triangles"] = double(m.face_count());
}
BENCHMARK(BM_BvhBuild)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Closest-point queries from random points around the 1M-triangle unit sphere, in random order
// (no spatial coherence, no hints). Arg 0: threads; arg 1: shell half-width in thousandths, the
// points' radius being uniform in [1 - w, 1 + w]. Near the surface (w = 0.01) the search visits
// about one root-to-leaf path and is bound by memory latency; farther out the curved surface has
// many nearly equidistant triangles and the search visits hundreds of nodes (inherent: near the
// centre of a sphere nothing can be pruned).
void BM_ClosestPointRandomOrder(benchmark::State& state) {
    static const TriangleBvh bvh(million_triangle_sphere());
    const auto threads = static_cast<unsigned>(state.range(0));
    const double width = double(state.range(1)) / 1000.0;
    const std::size_t queries = width > 0.05 ? 200'000 : 1'000'000;
    std::vector<glm::dvec3> points(queries);
    std::mt19937_64 rng(1);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> radius(1.0 - width, 1.0 + width);
    for (auto& p : points) p = radius(rng) * glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
    double checksum = 0.0;
    for (auto _ : state) {
        std::vector<double> partial(chunk_count(queries, 4096), 0.0);
        parallel_for_chunks(
            queries, 4096,
            [&](std::size_t c, std::size_t begin, std::size_t end) {
                double s = 0.0;
                for (std::size_t i = begin; i < end; ++i) s += bvh.closest_point(points[i]).distance;
                partial[c] = s;
            },
            threads);
        for (double s : partial) checksum += s;
    }
    benchmark::DoNotOptimize(checksum);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(queries));
}
BENCHMARK(BM_ClosestPointRandomOrder)
    ->Args({1, 10})
    ->Args({2, 10})
    ->Args({2, 200})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Coherent queries as surface_distance issues them: 1M area samples of a 100K-triangle sphere of
// radius 1.01, face by face with the previous answer as hint, against the 1M-triangle sphere.
// Includes generating the samples.
void BM_ClosestPointCoherent(benchmark::State& state) {
    static const TriangleBvh bvh(million_triangle_sphere());
    static const Mesh from = gimg::geo::make_uv_sphere(250, 201, 1.01);
    SurfaceDistanceOptions o;
    o.threads = static_cast<unsigned>(state.range(0));
    o.sampling.sample_count = 1'000'000;
    for (auto _ : state) {
        const DistanceStats d = one_sided_distance(from, bvh, o);
        benchmark::DoNotOptimize(d.mean);
    }
    state.SetItemsProcessed(std::int64_t(state.iterations()) * 1'000'000);
}
BENCHMARK(BM_ClosestPointCoherent)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// What `gimg compare` does for two 50K-triangle meshes: two BVH builds and 1M samples each way
// (the default: max(1M, 10 per face)).
void BM_Compare50K(benchmark::State& state) {
    const Mesh& a = fifty_k_sphere(1.0);
    const Mesh& b = fifty_k_sphere(1.05);
    SurfaceDistanceOptions o;
    o.threads = static_cast<unsigned>(state.range(0));
    for (auto _ : state) {
        const SurfaceDistance d = surface_distance(a, b, o);
        benchmark::DoNotOptimize(d.symmetric.mean);
    }
}
BENCHMARK(BM_Compare50K)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

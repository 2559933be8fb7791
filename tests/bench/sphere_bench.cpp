// Google Benchmark timings of the spherical parameterizations on the shared meshes (skipped when
// a mesh is missing). Run with ./run bench or build/tests/bench/gimg_sphere_bench.
#include "test_data.h"

#include "gimg/geometry/io.h"
#include "gimg/passes/sphere.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <map>
#include <string>

namespace {

// Loaded once per process: the timing is of the map, not of the file reader.
const gimg::geo::Mesh* shared_mesh(const std::string& name) {
    static std::map<std::string, gimg::geo::Mesh> loaded;
    if (auto it = loaded.find(name); it != loaded.end()) return &it->second;
    const auto path = gimg::test::shared_mesh(name);
    if (!path) return nullptr;
    return &loaded.emplace(name, gimg::geo::load_mesh(*path)).first->second;
}

// Everything sphere_linear does: input check, three sparse solves, and the flip count it reports.
void BM_SphereLinear(benchmark::State& state, const std::string& name) {
    const gimg::geo::Mesh* mesh = shared_mesh(name);
    if (!mesh) {
        state.SkipWithError(("shared mesh " + name + " not found (set GIMG_MESH_DIR)").c_str());
        return;
    }
    gimg::passes::SphereResult result;
    double wall = 0.0;
    for (auto _ : state) {
        const auto start = std::chrono::steady_clock::now();
        result = gimg::passes::sphere_linear(*mesh);
        wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        benchmark::DoNotOptimize(result.positions.data());
    }
    // The last run's split: its three stages, and the rest (input check, flip count).
    state.counters["vertices"] = double(mesh->vertex_count());
    const char* keys[] = {"harmonic_ms", "projection_ms", "beltrami_ms"};
    for (std::size_t i = 0; i < result.stages.size() && i < 3; ++i) {
        state.counters[keys[i]] = 1e3 * result.stages[i].seconds;
        wall -= result.stages[i].seconds;
    }
    state.counters["check_and_flips_ms"] = 1e3 * wall;
}
BENCHMARK_CAPTURE(BM_SphereLinear, bunny, std::string("bunny.off"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SphereLinear, armadillo, std::string("armadillo.off"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

// The base mesh's sphere map: a tetrahedron refined split by split (see base_map.h).
#include "sphere/hierarchy/base_map.h"

#include "sphere/weighted_graph.h"
#include "sphere/hierarchy/split_refinement.h"

#include <cmath>
#include <string>
#include <stdexcept>

namespace gimg::passes::detail {

namespace {

constexpr double kSweepTolerance = 1e-14;
constexpr std::size_t kSweepIterations = 100;

void map_tetrahedron(const geo::ProgressiveMesh& pm, std::vector<glm::dvec3>& y) {
    if (pm.coarsest_count() != 4)
        throw std::logic_error("sphere base map: the progressive mesh did not reach a tetrahedron");
    const double s = 1.0 / std::sqrt(3.0);
    const glm::dvec3 corners[4] = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
    for (int i = 0; i < 4; ++i) y[pm.coarsest_vertices[i]] = corners[i];
    const std::vector<glm::uvec3> faces = geo::triangles_at(pm, 4);
    // A mirror image if the corner order came out clockwise.
    if (count_flips(faces, y) != 0) std::swap(y[pm.coarsest_vertices[0]], y[pm.coarsest_vertices[1]]);
    if (count_flips(faces, y) != 0) throw std::logic_error("sphere base map: could not orient the tetrahedron");
}

// Gauss-Seidel sweeps of the kernel-checked vertex Tutte optimisation; returns the steps applied.
std::size_t tutte_sweeps(const WeightedGraph& g, std::vector<glm::dvec3>& y, std::size_t sweeps) {
    std::size_t applied = 0;
    for (std::size_t sweep = 0; sweep < sweeps; ++sweep)
        for (std::uint32_t v : g.vertices) {
            const VertexStep step = optimise_vertex(g.vertex_energy(v, y), 1.0, kSweepTolerance, kSweepIterations);
            if (step.energy_after < step.energy_before &&
                in_kernel(g.adjacency.faces_of_vertex(v), g.triangles, y, v, step.position)) {
                y[v] = step.position;
                ++applied;
            }
        }
    return applied;
}

}  // namespace

BaseMapRun map_base_mesh(const geo::Mesh& mesh, const geo::ProgressiveMesh& pm, geo::ProgressiveReplay& replay,
                         std::vector<glm::dvec3>& y) {
    BaseMapRun run;
    map_tetrahedron(pm, y);
    std::vector<glm::uvec3> triangles = replay.live_triangles();
    for (std::size_t count : geo::level_vertex_counts(pm.coarsest_count(), pm.base_vertex_count, 2.0)) {
        if (count == pm.coarsest_count()) continue;
        run.placement_failures += split_to(replay, y, count).placement_failures;
        const WeightedGraph g = make_weighted_graph(mesh, replay.live_triangles(), EdgeWeights::Uniform);
        run.vertex_steps += tutte_sweeps(g, y, kBaseMapSweeps);
        normalise_mass_centre(y, g.vertices, g.triangles);
        run.energy = g.energy(y);
        triangles = g.triangles;
    }
    run.flips = count_flips(triangles, y);
    return run;
}

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

HierarchyStart::HierarchyStart(const geo::Mesh& mesh, std::size_t base_vertices, double growth,
                               std::vector<glm::dvec3>& y, std::vector<SphereStage>& stages,
                               std::vector<std::string>& warnings, std::chrono::steady_clock::time_point since)
    : pm(geo::build_progressive_mesh(mesh, base_vertices)),
      counts(geo::level_vertex_counts(pm.base_vertex_count, pm.vertex_count, growth)), replay(pm, pm.coarsest_count()) {
    stages.push_back({"progressive mesh", pm.base_vertex_count, pm.splits.size(), seconds_since(since), 0.0});
    const auto base_start = std::chrono::steady_clock::now();
    base = map_base_mesh(mesh, pm, replay, y);
    stages.push_back({"base map", pm.base_vertex_count, base.vertex_steps, seconds_since(base_start), base.energy});
    if (base.placement_failures || base.flips)
        warnings.push_back("base map: " + std::to_string(base.placement_failures) +
                           " split vertices could not be placed, " + std::to_string(base.flips) + " flipped triangles");
}

}  // namespace gimg::passes::detail

// Step 1: the holes capped for the construction, and the critical structure of a harmonic function
// (Ni, Garland & Hart 2004, as Satoh & Imai and He et al. use it).
#include "polycube_parts.h"

#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/topology.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <unordered_map>

namespace gimg::passes {

namespace polycube {

std::vector<double> positive_cotangent_weights(const geo::Mesh& mesh, const geo::MeshAdjacency& adj) {
    std::vector<double> w = geo::cotangent_weights(mesh, adj);
    double mean = 0.0;
    for (double x : w) mean += std::abs(x);
    mean = w.empty() ? 1.0 : std::max(mean / double(w.size()), 1e-300);
    for (double& x : w) x = std::max(x, 1e-3 * mean);
    return w;
}

LinearSystem positive_laplacian(const geo::Mesh& mesh, const geo::MeshAdjacency& adj,
                                const std::vector<std::uint8_t>& fixed, const std::vector<double>& fixed_values,
                                std::uint32_t rhs_count) {
    const std::vector<double> w = positive_cotangent_weights(mesh, adj);

    const std::size_t n = mesh.vertex_count();
    LinearSystem s;
    s.rhs_count = rhs_count;
    s.a.size = n;
    s.a.offsets.assign(1, 0);
    s.b.assign(n * rhs_count, 0.0);
    s.fixed = fixed;
    s.fixed_values = fixed_values;
    for (std::size_t i = 0; i < n; ++i) {
        double diagonal = 0.0;
        const std::size_t diag_at = s.a.columns.size();
        s.a.columns.push_back(std::uint32_t(i));
        s.a.values.push_back(0.0);
        for (std::uint32_t k = adj.vertex_vertex_offsets[i]; k < adj.vertex_vertex_offsets[i + 1]; ++k) {
            const std::uint32_t j = adj.vertex_vertices[k];
            const double wij = w[adj.find_edge(std::uint32_t(i), j)];
            diagonal += wij;
            s.a.columns.push_back(j);
            s.a.values.push_back(-wij);
        }
        s.a.values[diag_at] = diagonal > 0.0 ? diagonal : 1.0;
        s.a.offsets.push_back(std::uint32_t(s.a.columns.size()));
    }
    return s;
}

SolveResult solve(Context* ctx, const LinearSystem& system, PolycubeStatistics& stats) {
    SolveOptions o;
    o.tolerance = 1e-10;
    o.max_iterations = 20000;
    const auto start = std::chrono::steady_clock::now();
    const SolveResult r = ctx ? solve_symmetric(*ctx, system, o) : solve_symmetric_cpu(system, o);
    stats.solve_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++stats.solves;
    stats.solve_iterations += r.iterations;
    return r;
}

std::vector<std::vector<std::uint32_t>> boundary_loops(const std::vector<glm::uvec3>& triangles) {
    // Each edge once per direction it is used in, sorted by its ends: an edge used one way only is
    // on a boundary, in that direction.
    std::vector<std::uint64_t> uses;  // (lower end << 33) | (higher end << 1) | (1 if from the higher)
    uses.reserve(3 * triangles.size());
    std::uint32_t vertices = 0;  // past the largest index: the arrays below cost little beside the sort
    for (const auto& t : triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            uses.push_back((std::uint64_t(std::min(a, b)) << 33) | (std::uint64_t(std::max(a, b)) << 1) | (a > b));
            vertices = std::max(vertices, a + 1);
        }
    std::sort(uses.begin(), uses.end());
    uses.erase(std::unique(uses.begin(), uses.end()), uses.end());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary;
    for (std::size_t i = 0; i < uses.size(); ++i) {
        if (i + 1 < uses.size() && uses[i + 1] >> 1 == uses[i] >> 1) {
            ++i;  // used both ways
            continue;
        }
        const auto lower = std::uint32_t(uses[i] >> 33), higher = std::uint32_t((uses[i] >> 1) & 0xffffffffu);
        if (lower == higher) continue;  // a triangle's repeated corner: its own reverse
        boundary.push_back(uses[i] & 1u ? std::pair{higher, lower} : std::pair{lower, higher});
    }
    std::sort(boundary.begin(), boundary.end());  // a vertex with two is named as before
    constexpr std::uint32_t kNoEdge = geo::kInvalidIndex;
    std::vector<std::uint32_t> next(vertices, kNoEdge);
    for (const auto& e : boundary) {
        if (next[e.first] != kNoEdge)
            throw geo::InputError("vertex " + std::to_string(e.first) +
                                  " lies on two boundary loops (a non-manifold vertex)");
        next[e.first] = e.second;
    }
    std::vector<std::vector<std::uint32_t>> loops;
    std::vector<std::uint8_t> seen(vertices, 0);
    for (std::uint32_t s = 0; s < vertices; ++s) {  // each loop from its smallest vertex
        if (next[s] == kNoEdge || seen[s]) continue;
        std::vector<std::uint32_t> loop;
        std::uint32_t v = s;
        while (!seen[v]) {
            seen[v] = 1;
            loop.push_back(v);
            if (next[v] == kNoEdge) throw geo::InputError("a boundary chain ends at vertex " + std::to_string(v));
            v = next[v];
        }
        if (v != s) throw geo::InputError("a boundary chain runs into another at vertex " + std::to_string(v));
        loops.push_back(std::move(loop));
    }
    return loops;
}

std::vector<std::uint32_t> join_across_edges(const std::vector<glm::uvec3>& triangles,
                                             const std::function<bool(std::uint32_t, std::uint32_t)>& same) {
    std::vector<std::uint32_t> root(triangles.size());
    std::iota(root.begin(), root.end(), 0u);
    const auto find = [&](std::uint32_t a) {
        while (root[a] != a) a = root[a] = root[root[a]];
        return a;
    };
    // Every edge with the triangles holding it, sorted by edge, then triangle.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
    edges.reserve(3 * triangles.size());
    for (std::uint32_t f = 0; f < triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) edges.push_back({edge_key(triangles[f][k], triangles[f][(k + 1) % 3]), f});
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
        const std::uint32_t first = edges[i].second;
        std::size_t j = i + 1;
        for (; j < edges.size() && edges[j].first == edges[i].first; ++j)
            if (same(first, edges[j].second)) root[find(edges[j].second)] = find(first);
        i = j;
    }
    for (std::uint32_t f = 0; f < root.size(); ++f) root[f] = find(f);
    return root;
}

}  // namespace polycube

CappedMesh cap_holes(const geo::Mesh& mesh) {
    const geo::MeshInfo info = geo::analyze_topology(mesh);
    if (mesh.face_count() == 0) throw geo::InputError("the mesh has no faces");
    if (info.nonfinite_vertices) throw geo::InputError("the mesh has vertices with NaN or infinite coordinates");
    if (info.components != 1)
        throw geo::InputError("the mesh has " + std::to_string(info.components) +
                              " pieces; a polycube needs one (gimg repair --largest keeps the largest)");
    if (!info.manifold)
        throw geo::InputError("the mesh is not manifold (non-manifold edges or vertices; gimg repair opens them)");
    if (!info.oriented)
        throw geo::InputError("the mesh's faces are not consistently oriented (gimg repair turns them)");
    if (info.degenerate_faces)
        throw geo::InputError("the mesh has " + std::to_string(info.degenerate_faces) +
                              " degenerate faces (gimg repair removes them)");
    CappedMesh c;
    c.mesh.positions = mesh.positions;
    c.mesh.triangles = mesh.triangles;
    c.original_vertices = mesh.vertex_count();
    c.original_faces = mesh.face_count();
    for (const auto& loop : polycube::boundary_loops(mesh.triangles)) {
        glm::dvec3 centre(0.0);
        for (std::uint32_t v : loop) centre += mesh.positions[v];
        const std::uint32_t apex = std::uint32_t(c.mesh.positions.size());
        c.mesh.positions.push_back(centre / double(loop.size()));
        // The loop runs with the surface on its left; the cap runs it the other way.
        for (std::size_t i = 0; i < loop.size(); ++i)
            c.mesh.triangles.push_back({loop[(i + 1) % loop.size()], loop[i], apex});
        ++c.loops;
    }
    return c;
}

std::size_t CriticalStructure::saddle_count() const {
    return std::accumulate(multiplicity.begin(), multiplicity.end(), std::size_t(0));
}

CriticalStructure critical_structure(Context* ctx, const geo::Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    if (n < 4) throw geo::InputError("the mesh has fewer than 4 vertices");
    CriticalStructure cs;
    const auto lower = [&](std::uint32_t a, std::uint32_t b) {  // z order, ties by index
        return mesh.positions[a].z < mesh.positions[b].z || (mesh.positions[a].z == mesh.positions[b].z && a < b);
    };
    std::vector<std::uint32_t> ids(n);
    std::iota(ids.begin(), ids.end(), 0u);
    cs.minimum = *std::min_element(ids.begin(), ids.end(), lower);
    cs.maximum = *std::max_element(ids.begin(), ids.end(), lower);

    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    std::vector<std::uint8_t> fixed(n, 0);
    std::vector<double> values(n, 0.0);
    fixed[cs.minimum] = fixed[cs.maximum] = 1;
    values[cs.maximum] = 1.0;
    PolycubeStatistics scratch;
    const SolveResult r = polycube::solve(ctx, polycube::positive_laplacian(mesh, adj, fixed, values, 1), scratch);
    cs.f = r.x;
    cs.iterations = r.iterations;
    cs.converged = r.converged;

    // The link of each vertex in order: the faces (v, a, b) give the link edge a -> b.
    const auto higher = [&](std::uint32_t u, std::uint32_t v) {
        return cs.f[u] > cs.f[v] || (cs.f[u] == cs.f[v] && u > v);
    };
    std::vector<std::uint32_t> next_in_link;
    for (std::uint32_t v = 0; v < n; ++v) {
        const auto faces = adj.faces_of_vertex(v);
        std::unordered_map<std::uint32_t, std::uint32_t> link;
        for (std::uint32_t f : faces) {
            const glm::uvec3 t = mesh.triangles[f];
            const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
            link[t[(k + 1) % 3]] = t[(k + 2) % 3];
        }
        if (link.empty()) continue;
        std::uint32_t start = link.begin()->first, u = start;
        int changes = 0;
        std::size_t steps = 0;
        do {
            const std::uint32_t w = link.count(u) ? link[u] : start;
            if (higher(u, v) != higher(w, v)) ++changes;
            u = w;
        } while (u != start && ++steps <= link.size());
        if (changes == 0) ++cs.extrema;
        if (changes >= 4) {
            cs.saddles.push_back(v);
            cs.multiplicity.push_back(std::uint32_t((changes - 2) / 2));
        }
    }
    return cs;
}

}  // namespace gimg::passes

// Flat neighbour lists with edge weights for one level of a sphere hierarchy.
#include "sphere/weighted_graph.h"

#include "gimg/geometry/cotangent.h"

namespace gimg::passes::detail {

WeightedGraph make_weighted_graph(const geo::Mesh& mesh, std::vector<glm::uvec3> triangles, EdgeWeights weights) {
    WeightedGraph g;
    geo::Mesh level;
    level.positions = mesh.positions;
    level.triangles = std::move(triangles);
    g.adjacency = geo::build_adjacency(level);
    std::vector<double> edge_weights;
    if (weights == EdgeWeights::Cotangent) edge_weights = geo::cotangent_weights(level, g.adjacency);
    const geo::MeshAdjacency& adj = g.adjacency;
    g.slot_weights.assign(adj.vertex_vertices.size(), 1.0);
    for (std::uint32_t v = 0; v < adj.vertex_count(); ++v) {
        if (adj.vertex_vertex_offsets[v] != adj.vertex_vertex_offsets[v + 1]) g.vertices.push_back(v);
        if (weights != EdgeWeights::Cotangent) continue;
        for (std::uint32_t j = adj.vertex_vertex_offsets[v]; j < adj.vertex_vertex_offsets[v + 1]; ++j)
            g.slot_weights[j] = edge_weights[adj.find_edge(v, adj.vertex_vertices[j])];
    }
    g.triangles = std::move(level.triangles);
    return g;
}

VertexEnergy WeightedGraph::vertex_energy(std::uint32_t v, const std::vector<glm::dvec3>& y) const {
    VertexEnergy e;
    e.origin = y[v];
    for (std::uint32_t j = adjacency.vertex_vertex_offsets[v]; j < adjacency.vertex_vertex_offsets[v + 1]; ++j) {
        const double w = slot_weights[j];
        const glm::dvec3 d = y[adjacency.vertex_vertices[j]] - y[v];
        e.laplacian += w * d;
        e.at_origin += w * glm::dot(d, d);
        e.weight_sum += w;
        e.abs_weight_sum += w < 0.0 ? -w : w;
    }
    return e;
}

double WeightedGraph::energy(const std::vector<glm::dvec3>& y) const {
    double sum = 0.0;
    for (std::uint32_t v : vertices)
        for (std::uint32_t j = adjacency.vertex_vertex_offsets[v]; j < adjacency.vertex_vertex_offsets[v + 1]; ++j) {
            const std::uint32_t u = adjacency.vertex_vertices[j];
            if (u < v) continue;  // each edge once
            const glm::dvec3 d = y[u] - y[v];
            sum += slot_weights[j] * glm::dot(d, d);
        }
    return sum;
}

}  // namespace gimg::passes::detail

#pragma once
// One mesh of a hierarchy (or the full mesh) as the CPU sphere solvers need it: CSR neighbours with
// an edge weight per neighbour slot, and the faces around each vertex for kernel checks.

#include "sphere/sphere_steps.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/mesh.h"

#include <vector>

namespace gimg::passes::detail {

enum class EdgeWeights {
    Uniform,    // 1 per edge: the Tutte energy E (eq. 1)
    Cotangent,  // (cot alpha + cot beta) / 2 on the mesh's own 3D geometry: the conformal energy F (eq. 2)
};

struct WeightedGraph {
    std::vector<glm::uvec3> triangles;
    // Built on all vertices of the full mesh; vertices not in `triangles` are isolated.
    geo::MeshAdjacency adjacency;
    // slot_weights[j]: weight of the edge from v to adjacency.vertex_vertices[j], j in v's CSR range.
    std::vector<double> slot_weights;
    std::vector<std::uint32_t> vertices;  // those in some triangle, ascending

    // S, W and sum |w| of v's neighbours, for optimise_vertex().
    VertexEnergy vertex_energy(std::uint32_t v, const std::vector<glm::dvec3>& y) const;
    // sum over edges of w_uv |y(u) - y(v)|^2.
    double energy(const std::vector<glm::dvec3>& y) const;
};

// `triangles` name vertices of `mesh` (original ids); cotangents use mesh.positions.
WeightedGraph make_weighted_graph(const geo::Mesh& mesh, std::vector<glm::uvec3> triangles, EdgeWeights weights);

}  // namespace gimg::passes::detail

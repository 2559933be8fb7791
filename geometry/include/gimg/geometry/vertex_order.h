#pragma once
// Vertices renumbered so that neighbours on the surface get nearby numbers. Solvers that gather
// each vertex's neighbours (sparse matrix products, relaxation sweeps) then find them in the same
// cache lines: meshes refined by subdivision number the new vertices after all the old ones, so a
// vertex's neighbours lie a quarter of the mesh apart (armadillo_loop1: 22,000 indices on
// average), and every gather misses the cache.
#include "gimg/geometry/mesh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace gimg::geo {

// order[k] = the index of the point that comes k-th along a Morton (Z-order) curve through the
// points' bounding box, cut into 2^bits_per_axis cells an axis (1 to 21); points in one cell keep
// their order. Fewer bits sort faster (a radix pass per 11 bits of key).
std::vector<std::uint32_t> morton_order(std::span<const glm::dvec3> points, int bits_per_axis = 21);

// order[k] = the old index of the vertex that becomes vertex k: morton_order of the positions.
std::vector<std::uint32_t> spatial_vertex_order(const Mesh& mesh);

// The same mesh with vertex k = old vertex order[k] (positions, texture coordinates and normals
// moved with it, triangles renumbered). `order` must be a permutation of the vertices.
Mesh reorder_vertices(const Mesh& mesh, const std::vector<std::uint32_t>& order);

// Per-vertex values of the reordered mesh back in the original numbering: out[order[k]] = v[k].
template <class T>
std::vector<T> original_vertex_order(const std::vector<T>& v, const std::vector<std::uint32_t>& order) {
    std::vector<T> out(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) out[order[k]] = v[k];
    return out;
}

}  // namespace gimg::geo

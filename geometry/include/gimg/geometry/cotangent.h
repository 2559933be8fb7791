#pragma once
// Cotangent Laplacian weights and one-ring vertex areas, the building blocks of the discrete
// Laplace-Beltrami operator (curvature, conformal and harmonic maps).

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <vector>

namespace gimg::geo {

// Cotangents are clamped to +-kMaxCotangent (an angle of about 1e-8 rad from 0 or pi), so a
// degenerate triangle gives a large but finite weight, never Inf or NaN.
inline constexpr double kMaxCotangent = 1e8;

// Cotangent of the angle between u and v (dot / |cross|), clamped as above; 0 when u or v has
// zero length (the angle is undefined and the corner contributes nothing).
double clamped_cotangent(const glm::dvec3& u, const glm::dvec3& v);

// Per edge of `adjacency`: sum over its incident faces of 1/2 cot(angle opposite the edge).
// A manifold interior edge gets the usual (cot alpha + cot beta) / 2, a boundary edge one term,
// a non-manifold edge one term per face. Faces that repeat a vertex contribute nothing.
std::vector<double> cotangent_weights(const Mesh& mesh, const MeshAdjacency& adjacency);

enum class VertexAreaKind {
    // A third of the area of every incident face.
    Barycentric,
    // Meyer, Desbrun, Schroeder & Barr (2003) "mixed" area: the Voronoi region inside non-obtuse
    // triangles; in an obtuse triangle half its area to the obtuse corner, a quarter to the
    // others. Tiles the surface (areas sum to the total area) and is the area that makes the
    // cotangent mean-curvature formula consistent.
    MixedVoronoi,
};

// Area associated with each vertex; 0 for a vertex in no face.
std::vector<double> vertex_areas(const Mesh& mesh, VertexAreaKind kind);

}  // namespace gimg::geo

#pragma once
// Per-face and per-vertex differential quantities of first order: face normals and areas, corner
// angles and angle-weighted vertex normals.

#include "gimg/geometry/mesh.h"

#include <glm/vec3.hpp>

#include <vector>

namespace gimg::geo {

// Angle at corner a of the triangle (a, b, c) in radians, in [0, pi]. atan2 of |cross| and dot
// stays accurate for angles near 0 and pi, and gives 0 (not NaN) when an edge has zero length.
double corner_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// Unit normal of each face, oriented by the counter-clockwise corner order (right-hand rule);
// the zero vector for a degenerate (zero-area) face.
std::vector<glm::dvec3> face_normals(const Mesh& mesh);

// Area of each face (half the length of the edge cross product).
std::vector<double> face_areas(const Mesh& mesh);

// The three corner angles of every face: angles[3f + k] at corner k of triangle f.
std::vector<double> corner_angles(const Mesh& mesh);

// Unit vertex normals: the sum of the incident face normals weighted by the face's angle at the
// vertex (Thuermer & Wuethrich), which does not depend on how a flat region is triangulated.
// Vertices in no face, or whose weighted sum cancels out, get the zero vector.
std::vector<glm::dvec3> vertex_normals(const Mesh& mesh);

}  // namespace gimg::geo

#pragma once
// Procedural meshes with known geometry: analytic test cases and the demo's default input, so
// nothing needs a mesh file.

#include "gimg/geometry/mesh.h"

namespace gimg::geo {

// Subdivided icosahedron projected onto the sphere of `radius` around `center`: 10*4^level + 2
// vertices, closed, genus 0, outward counter-clockwise faces.
Mesh make_icosphere(double radius, int level, glm::dvec3 center = glm::dvec3(0.0));

// Latitude-longitude sphere: `segments` around, `rings` bands from pole to pole (rings >= 2),
// 2 * segments * (rings - 1) faces. Its thin triangles near the poles are a different
// tessellation from the icosphere's, which some tests want.
Mesh make_uv_sphere(int segments, int rings, double radius = 1.0, glm::dvec3 center = glm::dvec3(0.0));

// Axis-aligned box with the given edge lengths around the origin, each face split into
// `divisions` x `divisions` quads (two triangles each); vertices shared along edges.
Mesh make_box(glm::dvec3 size, int divisions = 1);

// A grid of nx x ny quads spanning [0, width] x [0, height] in the z = 0 plane, facing +z, with
// texture coordinates (x / width, y / height).
Mesh make_grid(int nx, int ny, double width = 1.0, double height = 1.0);

// Torus around the y axis: ring radius R, tube radius r, n_ring x n_tube quads. Genus 1.
Mesh make_torus(double R, double r, int n_ring, int n_tube);

}  // namespace gimg::geo

#pragma once
// A vertex's one-ring flattened by MAPS's z^a map (eq. 2) and the polygon re-triangulated by a
// constrained Delaunay triangulation: the chart in which a removed vertex's hole is refilled.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace gimg::passes {

struct Ring {
    std::vector<std::uint32_t> ring;    // neighbours counter-clockwise
    std::vector<std::uint32_t> faces;   // faces[k] = (centre, ring[k], ring[k+1])
    std::vector<glm::dvec2> mu;         // z^a images of the ring, the centre at the origin
    std::vector<glm::uvec3> triangles;  // the refill, as indices into ring, counter-clockwise
};

// The one-ring of v from its incident faces (vertex_faces[v] into faces): false when they do not
// form one closed fan.
bool gather_ring(const std::vector<glm::uvec3>& faces, const std::vector<std::uint32_t>& vertex_faces, std::uint32_t v,
                 Ring& r);

// The angle at `apex` of triangle (apex, a, b), in [0, pi].
double corner_angle(glm::dvec3 apex, glm::dvec3 a, glm::dvec3 b);

// mu_k = (r_k / max r)^a exp(i a theta_k), a = 2 pi / (total angle), except that a sector z^a
// would open to 0.9 pi or more is held there and the other sectors share the rest of 2 pi, so the
// fan stays one-to-one and its polygon star-shaped about the centre. False for a degenerate corner.
// `polar`: radii r_k / max r (angles still scaled by a), which does not shrink cone tips as r^a.
// `max_cone` > 0: false when a > max_cone or a < 1 / max_cone (a cone tip or a deep saddle).
bool flatten_ring(const std::vector<glm::dvec3>& positions, std::uint32_t centre, Ring& r, bool polar = false,
                  double max_cone = 0.0);

// Ear clipping, then Lawson flips until every diagonal is locally Delaunay: K - 2 triangles with
// edges between ring vertices only. `forbidden` (K x K, or empty) marks diagonals that may not be
// used (edges the mesh already has elsewhere); they are never cut or flipped to, so the result is
// the Delaunay refill constrained to avoid them. False when no ear can be cut.
bool triangulate_ring(Ring& r, const std::vector<std::uint8_t>& forbidden = {});

struct Location {
    std::uint32_t triangle = 0;  // index into r.triangles
    glm::dvec3 bary{1, 0, 0};    // clamped to the triangle and summing to 1
};

// The refill triangle holding point p of the chart: the one whose smallest barycentric coordinate
// is largest, so a point on an edge or pushed out by round-off still finds one.
Location locate(const Ring& r, glm::dvec2 p);

// Barycentric coordinates of p in the 2D triangle (a, b, c) (not clamped; all -1 when degenerate).
glm::dvec3 barycentric_2d(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c);

}  // namespace gimg::passes

// Shared by the sphere solver's shaders: the points, the fan layout of passes/sphere/harmonic/relaxation_mesh.h
// and the orientation test (same arithmetic as the CPU reference). All in storage images, one
// texel an element (gimg/engine/texel_array.h says why: lavapipe gathers from images, and loads from
// storage buffers lane by lane): the points in RGBA32UI, two texels a point, (x, y) and (z, 0) as
// doubles; the fans' offsets in R32UI; their spokes in RGBA32UI, (neighbour, 0, weight as a
// double). The including shader declares the images `points`, `ring_offsets` and `spokes`.
#include "common/texel_array.glsl"

dvec3 point_at(uint v) {
    const uvec4 xy = imageLoad(points, texel(2u * v));
    const uvec2 z = imageLoad(points, texel(2u * v + 1u)).xy;
    return dvec3(packDouble2x32(xy.xy), packDouble2x32(xy.zw), packDouble2x32(z));
}
uint ring_offset(uint v) { return imageLoad(ring_offsets, texel(v)).x; }
uint spoke_vertex(uint k) { return imageLoad(spokes, texel(k)).x; }
double spoke_weight(uint k) { return packDouble2x32(imageLoad(spokes, texel(k)).zw); }

// The kernel test of passes/sphere/sphere_steps.h: counter-clockwise seen from outside by a
// rounding margin, det(a, b, c) written a . ((b - a) x (c - a)) to keep its precision on tiny
// triangles.
const double kKernelMargin = 1e-12LF;
const double kRelaxMargin = 1e-6LF;  // passes/sphere/harmonic/relaxation_mesh.h says why
bool counter_clockwise(dvec3 a, dvec3 b, dvec3 c, double margin) {
    const dvec3 ab = b - a, ac = c - a;
    const double det = dot(a, cross(ab, ac));
    // det > margin |ab| |ac| without the square root (the margin is positive).
    return det > 0.0LF && det * det > margin * margin * (dot(ab, ab) * dot(ac, ac));
}

// Orientation grades and the per-triangle rule of passes/sphere/sphere_level.cpp: 2 passes the
// relaxation test, 1 only the kernel test, 0 neither; a move may lower no triangle's grade, and
// may turn no triangle of grade 0 further clockwise (there the sign of det is rounding noise).
int orientation_grade(dvec3 at, dvec3 a, dvec3 b) {
    if (counter_clockwise(at, a, b, kRelaxMargin)) return 2;
    return counter_clockwise(at, a, b, kKernelMargin) ? 1 : 0;
}

double orientation(dvec3 at, dvec3 a, dvec3 b) { return dot(at, cross(a - at, b - at)); }

bool keeps_every_grade(uint v, dvec3 from, dvec3 to) {
    const uint begin = ring_offset(v), degree = ring_offset(v + 1) - begin;
    // Each neighbour loaded once: triangle k's second corner is triangle k + 1's first.
    const dvec3 first = point_at(spoke_vertex(begin));
    dvec3 b = first;
    for (uint k = 0; k < degree; ++k) {
        const dvec3 a = b;
        b = k + 1 < degree ? point_at(spoke_vertex(begin + k + 1)) : first;
        const int after = orientation_grade(to, a, b);
        if (after == 2) continue;
        const int before = orientation_grade(from, a, b);
        if (after < before) return false;
        if (after == 0 && before == 0 && orientation(to, a, b) < orientation(from, a, b)) return false;
    }
    return true;
}

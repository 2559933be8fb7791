// Shared by the sphere solver's shaders: points as dvec4 (w unused), the fan layout of
// passes/sphere/sphere_level.h, and the orientation test (same arithmetic as the CPU reference).
// A point is one vector load, not three: lavapipe loads storage buffers lane by lane, one loop
// per load, and fewer loads made a sweep about 15 % faster there.

dvec3 point_at(uint v) { return pos[v].xyz; }

// The kernel test of passes/sphere/sphere_steps.h: counter-clockwise seen from outside by a
// rounding margin, det(a, b, c) written a . ((b - a) x (c - a)) to keep its precision on tiny
// triangles.
const double kKernelMargin = 1e-12LF;
const double kRelaxMargin = 1e-6LF;  // passes/sphere/sphere_level.h says why
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
    const uint begin = ring_offsets[v], degree = ring_offsets[v + 1] - begin;
    // Each neighbour loaded once: triangle k's second corner is triangle k + 1's first.
    const dvec3 first = point_at(ring[begin]);
    dvec3 b = first;
    for (uint k = 0; k < degree; ++k) {
        const dvec3 a = b;
        b = k + 1 < degree ? point_at(ring[begin + k + 1]) : first;
        const int after = orientation_grade(to, a, b);
        if (after == 2) continue;
        const int before = orientation_grade(from, a, b);
        if (after < before) return false;
        if (after == 0 && before == 0 && orientation(to, a, b) < orientation(from, a, b)) return false;
    }
    return true;
}

// Shared by the sphere solver's shaders: points as interleaved doubles, the fan layout of
// passes/sphere/sphere_level.h, and the orientation test (same arithmetic as the CPU reference).

dvec3 point_at(uint v) { return dvec3(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]); }

// a . ((b - a) x (c - a)): det(a, b, c) with its precision kept on tiny triangles.
double orientation(dvec3 a, dvec3 b, dvec3 c) { return dot(a, cross(b - a, c - a)); }

uint flipped_in_fan(uint v, dvec3 at) {
    const uint begin = ring_offsets[v], degree = ring_offsets[v + 1] - begin;
    uint flipped = 0;
    for (uint k = 0; k < degree; ++k) {
        const uint a = ring[begin + k], b = ring[begin + (k + 1) % degree];
        if (!(orientation(at, point_at(a), point_at(b)) > 0.0LF)) ++flipped;
    }
    return flipped;
}

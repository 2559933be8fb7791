#version 460
#extension GL_GOOGLE_include_directive : require
// Per vertex, the terms of the level's statistics, summed afterwards by primitives/reduce_f64:
// the point (mass centre), half the energy of its spokes (each edge is seen from both ends), and
// among the triangles of its fan that it is the smallest index of (each counted once) the
// flipped ones and those failing the kernel test.
// map_stats_cpu in passes/sphere/sphere_level.cpp is the CPU reference.
layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D points;
layout(binding = 1, r32ui) uniform readonly uimage2D ring_offsets;
layout(binding = 2, rgba32ui) uniform readonly uimage2D spokes;
layout(std430, binding = 3) writeonly buffer Terms { double terms[]; };  // 6 per vertex
layout(push_constant) uniform Push { uint vertex_count; };

#include "sphere/sphere_common.glsl"

void main() {
    const uint v = gl_GlobalInvocationID.x;
    if (v >= vertex_count) return;
    const dvec3 y = point_at(v);
    const uint begin = ring_offset(v), degree = ring_offset(v + 1) - begin;
    double energy = 0.0LF, flips = 0.0LF, kernel_failures = 0.0LF;
    // Each neighbour loaded once: triangle k's second corner is triangle k + 1's first.
    const uint first = spoke_vertex(begin);
    const dvec3 first_point = point_at(first);
    uint b = first;
    dvec3 pb = first_point;
    for (uint k = 0; k < degree; ++k) {
        const uint a = b;
        const dvec3 pa = pb;
        b = k + 1 < degree ? spoke_vertex(begin + k + 1) : first;
        pb = k + 1 < degree ? point_at(b) : first_point;
        const dvec3 d = y - pa;
        energy += 0.5LF * spoke_weight(begin + k) * dot(d, d);
        if (v < a && v < b) {
            if (!counter_clockwise(y, pa, pb, kKernelMargin)) kernel_failures += 1.0LF;
            if (!(dot(y, cross(pa - y, pb - y)) > 0.0LF)) flips += 1.0LF;
        }
    }
    terms[6 * v] = y.x;
    terms[6 * v + 1] = y.y;
    terms[6 * v + 2] = y.z;
    terms[6 * v + 3] = energy;
    terms[6 * v + 4] = flips;
    terms[6 * v + 5] = kernel_failures;
}

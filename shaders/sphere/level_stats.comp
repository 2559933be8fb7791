#version 460
#extension GL_GOOGLE_include_directive : require
// Per vertex, the terms of the level's statistics, summed afterwards by primitives/reduce_f64:
// area * point (mass centre), half the energy of its spokes (each edge is seen from both ends),
// and the flipped triangles of its fan that it is the smallest index of (each counted once).
// level_stats_cpu in passes/sphere/sphere_level.cpp is the CPU reference.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Points { double pos[]; };
layout(std430, binding = 1) readonly buffer RingOffsets { uint ring_offsets[]; };
layout(std430, binding = 2) readonly buffer Ring { uint ring[]; };
layout(std430, binding = 3) readonly buffer RingWeights { double ring_weights[]; };
layout(std430, binding = 4) readonly buffer Areas { double vertex_areas[]; };
layout(std430, binding = 5) writeonly buffer Terms { double terms[]; };  // 5 per vertex
layout(push_constant) uniform Push { uint vertex_count; };

#include "sphere/sphere_common.glsl"

void main() {
    const uint v = gl_GlobalInvocationID.x;
    if (v >= vertex_count) return;
    const dvec3 y = point_at(v);
    const uint begin = ring_offsets[v], degree = ring_offsets[v + 1] - begin;
    double energy = 0.0LF, flips = 0.0LF;
    for (uint k = 0; k < degree; ++k) {
        const uint a = ring[begin + k], b = ring[begin + (k + 1) % degree];
        const dvec3 d = y - point_at(a);
        energy += 0.5LF * ring_weights[begin + k] * dot(d, d);
        if (v < a && v < b && !(orientation(y, point_at(a), point_at(b)) > 0.0LF)) flips += 1.0LF;
    }
    const dvec3 weighted = vertex_areas[v] * y;
    terms[5 * v] = weighted.x;
    terms[5 * v + 1] = weighted.y;
    terms[5 * v + 2] = weighted.z;
    terms[5 * v + 3] = energy;
    terms[5 * v + 4] = flips;
}

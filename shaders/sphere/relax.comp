#version 460
#extension GL_GOOGLE_include_directive : require
// One colour class of the relaxation (passes/sphere/sphere_level.cpp, relaxed_position, is the
// CPU reference): each vertex moves towards normalize(sum of w * neighbour), the minimiser of its
// local energy on the sphere, halving the step until no triangle of its fan flips that was not
// flipped before. No two vertices of one colour share an edge, so the moves are independent.
layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform uimage2D points;
layout(binding = 1, r32ui) uniform readonly uimage2D ring_offsets;
layout(binding = 2, rgba32ui) uniform readonly uimage2D spokes;
layout(binding = 3, r32ui) uniform readonly uimage2D members;
layout(push_constant) uniform Push {
    uint first;            // of this colour in members
    uint count;
    uint uniform_weights;  // 1: Tutte step (all weights 1)
};

#include "sphere/sphere_common.glsl"

const int kMaxStepHalvings = 16;

void main() {
    if (gl_GlobalInvocationID.x >= count) return;
    const uint v = imageLoad(members, texel(first + gl_GlobalInvocationID.x)).x;
    dvec3 sum = dvec3(0.0LF);
    for (uint k = ring_offset(v); k < ring_offset(v + 1); ++k)
        sum += (uniform_weights != 0 ? 1.0LF : spoke_weight(k)) * point_at(spoke_vertex(k));
    const double len = length(sum);
    if (!(len > 1e-300LF)) return;
    const dvec3 target = sum / len;
    const dvec3 current = point_at(v);
    double t = 1.0LF;
    for (int attempt = 0; attempt <= kMaxStepHalvings; ++attempt, t *= 0.5LF) {
        const dvec3 chord = current + t * (target - current);
        const double chord_length = length(chord);
        if (!(chord_length > 1e-12LF)) continue;
        const dvec3 candidate = chord / chord_length;
        if (keeps_every_grade(v, current, candidate)) {
            imageStore(points, texel(2u * v), uvec4(unpackDouble2x32(candidate.x), unpackDouble2x32(candidate.y)));
            imageStore(points, texel(2u * v + 1u), uvec4(unpackDouble2x32(candidate.z), 0u, 0u));
            return;
        }
    }
}

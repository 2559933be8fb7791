#version 460
#extension GL_GOOGLE_include_directive : require
// Moves the mass centre c of the points towards the sphere's centre by the Moebius transformation
// T_a(x) = (1 - |a|^2)(x - a) / |x - a|^2 - a, a = scale * c with |a| <= 1/2 (moebius_move in
// passes/sphere/sphere_steps.h). It is conformal, so it adds no angle distortion (Gu's
// normalize(y - c) does). It writes a separate image: the host keeps the result only if it
// flipped nothing, and halves the scale otherwise. Points as in sphere_common.glsl.
#include "common/texel_array.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D points;
layout(std430, binding = 1) readonly buffer Sums { double sums[]; };  // map_stats, reduced
layout(std430, binding = 2) readonly buffer Control { double scale; };
layout(binding = 3, rgba32ui) uniform writeonly uimage2D moved;
layout(push_constant) uniform Push { uint vertex_count; };

void main() {
    const uint v = gl_GlobalInvocationID.x;
    if (v >= vertex_count) return;
    dvec3 a = scale * dvec3(sums[0], sums[1], sums[2]) / double(vertex_count);
    if (length(a) > 0.5LF) a *= 0.5LF / length(a);
    const uvec4 xy = imageLoad(points, texel(2u * v));
    const uvec4 z = imageLoad(points, texel(2u * v + 1u));
    const dvec3 d = dvec3(packDouble2x32(xy.xy), packDouble2x32(xy.zw), packDouble2x32(z.xy)) - a;
    const dvec3 y = normalize((1.0LF - dot(a, a)) * d / dot(d, d) - a);
    imageStore(moved, texel(2u * v), uvec4(unpackDouble2x32(y.x), unpackDouble2x32(y.y)));
    imageStore(moved, texel(2u * v + 1u), uvec4(unpackDouble2x32(y.z), 0u, 0u));
}

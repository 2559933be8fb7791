#version 460
// Conjugate gradient, pass 2: alpha = r.z / p.q, x += alpha p, r -= alpha q, and r rounded to
// float for the multigrid cycle (r32). alpha is 0 when p.q is not positive (converged exactly).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer PQ { double pq; };
layout(std430, binding = 1) readonly buffer RZ { double rz; };
layout(binding = 2, rgba32ui) uniform readonly uimage2D p;
layout(binding = 3, rgba32ui) uniform readonly uimage2D q;
layout(binding = 4, rgba32ui) uniform uimage2D x;
layout(binding = 5, rgba32ui) uniform uimage2D r;
layout(binding = 6, rg32f) uniform writeonly image2D r32;
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const double alpha = pq > 0.0LF ? rz / pq : 0.0LF;
    const dvec2 ri = LOAD_VEC(r, i) - alpha * LOAD_VEC(q, i);
    STORE_VEC(x, i, LOAD_VEC(x, i) + alpha * LOAD_VEC(p, i));
    STORE_VEC(r, i, ri);
    STORE_VEC32(r32, i, vec2(ri));
}

#version 460
// BiCGSTAB, pass 5: x += alpha y + omega z, r = s - omega t, and the terms of r0 . r (0-1) and
// r . r (2-3) per right-hand side.
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"
#include "solvers/bicgstab_scalars.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Scalars { BicgScalars s; };
layout(binding = 1, rgba32ui) uniform readonly uimage2D y;
layout(binding = 2, rgba32ui) uniform readonly uimage2D z;
layout(binding = 3, rgba32ui) uniform readonly uimage2D s_vec;
layout(binding = 4, rgba32ui) uniform readonly uimage2D t;
layout(binding = 5, rgba32ui) uniform readonly uimage2D r0;
layout(binding = 6, rgba32ui) uniform uimage2D x;
layout(binding = 7, rgba32ui) uniform writeonly uimage2D r;
layout(std430, binding = 8) writeonly buffer Terms { double terms[]; };
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    STORE_VEC(x, i, LOAD_VEC(x, i) + s.alpha * LOAD_VEC(y, i) + s.omega * LOAD_VEC(z, i));
    const dvec2 ri = LOAD_VEC(s_vec, i) - s.omega * LOAD_VEC(t, i);
    STORE_VEC(r, i, ri);
    const dvec2 r0i = LOAD_VEC(r0, i);
    terms[4 * i + 0] = r0i.x * ri.x;
    terms[4 * i + 1] = r0i.y * ri.y;
    terms[4 * i + 2] = ri.x * ri.x;
    terms[4 * i + 3] = ri.y * ri.y;
}

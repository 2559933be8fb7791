#version 460
// BiCGSTAB, pass 1: p = r + beta (p - omega v), and the preconditioner's input: with Jacobi
// y = D^-1 p itself (the rows image carries 1 / a_ii), with the multigrid cycle p rounded to float
// (p32), which the cycle turns into y.
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"
#include "solvers/bicgstab_scalars.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Scalars { BicgScalars s; };
layout(binding = 1, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 2, rgba32ui) uniform readonly uimage2D r;
layout(binding = 3, rgba32ui) uniform readonly uimage2D v;
layout(binding = 4, rgba32ui) uniform uimage2D p;
layout(binding = 5, rgba32ui) uniform writeonly uimage2D y;
layout(binding = 6, rg32f) uniform writeonly image2D p32;
layout(push_constant) uniform Push { uint rows; uint multigrid; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const dvec2 pi = LOAD_VEC(r, i) + s.beta * (LOAD_VEC(p, i) - s.omega * LOAD_VEC(v, i));
    STORE_VEC(p, i, pi);
    if (multigrid != 0u)
        STORE_VEC32(p32, i, vec2(pi));
    else
        STORE_VEC(y, i, value_of(imageLoad(a_rows, texel(i))) * pi);
}

#version 460
// BiCGSTAB, pass 3: s = r - alpha v, and the preconditioner's input: with Jacobi z = D^-1 s itself,
// with the multigrid cycle s rounded to float (s32).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"
#include "solvers/bicgstab_scalars.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Scalars { BicgScalars s; };
layout(binding = 1, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 2, rgba32ui) uniform readonly uimage2D r;
layout(binding = 3, rgba32ui) uniform readonly uimage2D v;
layout(binding = 4, rgba32ui) uniform writeonly uimage2D s_vec;
layout(binding = 5, rgba32ui) uniform writeonly uimage2D z;
layout(binding = 6, rg32f) uniform writeonly image2D s32;
layout(push_constant) uniform Push { uint rows; uint multigrid; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const dvec2 si = LOAD_VEC(r, i) - s.alpha * LOAD_VEC(v, i);
    STORE_VEC(s_vec, i, si);
    if (multigrid != 0u)
        STORE_VEC32(s32, i, vec2(si));
    else
        STORE_VEC(z, i, value_of(imageLoad(a_rows, texel(i))) * si);
}

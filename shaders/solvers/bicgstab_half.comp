#version 460
// BiCGSTAB, pass 3: s = r - alpha v, z = D^-1 s.
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
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const dvec2 si = LOAD_VEC(r, i) - s.alpha * LOAD_VEC(v, i);
    STORE_VEC(s_vec, i, si);
    STORE_VEC(z, i, value_of(imageLoad(a_rows, texel(i))) * si);
}

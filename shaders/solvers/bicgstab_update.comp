#version 460
// BiCGSTAB, pass 5: x += alpha y + omega z, r = s - omega t, and the workgroup's sums of r0 . r
// (0-1) and r . r (2-3) per right-hand side for bicgstab_finish. y and z are the double vectors
// (Jacobi) or the multigrid cycle's float outputs, widened as they are read (exactly).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"
#include "solvers/bicgstab_scalars.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Scalars { BicgScalars s; };
layout(binding = 1, rgba32ui) uniform readonly uimage2D y;
layout(binding = 2, rgba32ui) uniform readonly uimage2D z;
layout(binding = 3, rg32f) uniform readonly image2D y32;
layout(binding = 4, rg32f) uniform readonly image2D z32;
layout(binding = 5, rgba32ui) uniform readonly uimage2D s_vec;
layout(binding = 6, rgba32ui) uniform readonly uimage2D t;
layout(binding = 7, rgba32ui) uniform readonly uimage2D r0;
layout(binding = 8, rgba32ui) uniform uimage2D x;
layout(binding = 9, rgba32ui) uniform writeonly uimage2D r;
layout(std430, binding = 10) writeonly buffer Partials { double partials[]; };
layout(push_constant) uniform Push { uint rows; uint float_input; };

#include "solvers/workgroup_sums.glsl"

void main() {
    const uint i = gl_GlobalInvocationID.x;
    dvec4 terms = dvec4(0.0LF);
    if (i < rows) {
        const dvec2 yi = float_input != 0u ? dvec2(LOAD_VEC32(y32, i)) : LOAD_VEC(y, i);
        const dvec2 zi = float_input != 0u ? dvec2(LOAD_VEC32(z32, i)) : LOAD_VEC(z, i);
        STORE_VEC(x, i, LOAD_VEC(x, i) + s.alpha * yi + s.omega * zi);
        const dvec2 ri = LOAD_VEC(s_vec, i) - s.omega * LOAD_VEC(t, i);
        STORE_VEC(r, i, ri);
        terms = dvec4(LOAD_VEC(r0, i) * ri, ri * ri);
    }
    write_workgroup_sums(terms);
}

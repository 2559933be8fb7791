#version 460
// Conjugate gradient, pass 3 (after the multigrid cycle z = M r, in float, and r.z):
// p = z + beta p, beta = (new r.z) / (old r.z).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer OldRZ { double rz_old; };
layout(std430, binding = 1) readonly buffer NewRZ { double rz_new; };
layout(binding = 2, rg32f) uniform readonly image2D z;
layout(binding = 3, rgba32ui) uniform uimage2D p;
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const double beta = rz_old > 0.0LF ? rz_new / rz_old : 0.0LF;
    STORE_VEC(p, i, dvec2(LOAD_VEC32(z, i)) + beta * LOAD_VEC(p, i));
}

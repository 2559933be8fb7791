#version 460
// BiCGSTAB with the multigrid cycle: the cycle's float output widened to the solver's double
// vectors (y or z).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rg32f) uniform readonly image2D in32;
layout(binding = 1, rgba32ui) uniform writeonly uimage2D out_vec;
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    STORE_VEC(out_vec, i, dvec2(LOAD_VEC32(in32, i)));
}

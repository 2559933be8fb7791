#version 460
// Multigrid V-cycle: the coarsest level's exact solve, x = inverse(A) b with the dense inverse
// the host computed (at most a few hundred rows). When the problem is that small the dense level
// is the whole cycle, and it also writes row i's term of r . z (write_terms; b is r there).
#extension GL_GOOGLE_include_directive : require
#include "sphere/texels.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inverse { double inverse[]; };
layout(binding = 1, rgba32ui) uniform readonly uimage2D b;
layout(binding = 2, rgba32ui) uniform writeonly uimage2D x;
layout(std430, binding = 3) writeonly buffer Terms { double terms[]; };
layout(push_constant) uniform Push { uint rows; uint write_terms; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    dvec2 sum = dvec2(0.0LF);
    for (uint j = 0; j < rows; ++j) sum += inverse[i * rows + j] * LOAD_VEC(b, j);
    STORE_VEC(x, i, sum);
    if (write_terms != 0u) terms[i] = dot(LOAD_VEC(b, i), sum);
}

#version 460
// Multigrid V-cycle: the coarsest level's exact solve, x = inverse(A) b with the dense inverse
// the host computed (at most a few hundred rows; an image, which lavapipe gathers from, where a
// buffer took 0.24 ms a cycle at 191 rows), summed in double from the cycle's float b
// (`precise`: mg_presmooth_first says why). When the problem is that small the dense level is the
// whole cycle, and it also writes row i's term of r . z (write_terms; b is r, rounded to float,
// there).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rg32ui) uniform readonly uimage2D inverse;  // row-major, one double a texel
layout(binding = 1, rg32f) uniform readonly image2D b;
layout(binding = 2, rg32f) uniform writeonly image2D x;
layout(std430, binding = 3) writeonly buffer Terms { double terms[]; };
layout(push_constant) uniform Push { uint rows; uint write_terms; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    precise dvec2 sum = dvec2(0.0LF);
    for (uint j = 0; j < rows; ++j) sum += packDouble2x32(imageLoad(inverse, texel(i * rows + j)).xy) * dvec2(LOAD_VEC32(b, j));
    const vec2 xi = vec2(sum);
    STORE_VEC32(x, i, xi);
    if (write_terms != 0u) terms[i] = dot(dvec2(LOAD_VEC32(b, i)), dvec2(xi));
}

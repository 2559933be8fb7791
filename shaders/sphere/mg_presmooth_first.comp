#version 460
// Multigrid V-cycle, on the way down, pass 1 of the Chebyshev smoother from zero: the first step
// x1 = D^-1 b / theta, its residual r1 = b - A x1, and what pass 2 needs of them,
// mix = c0 b + c1 r1 (the smoother's result is D^-1 mix). The entries come divided by their
// column's diagonal (a_ij / a_jj).
// apply_multigrid_cpu in passes/sphere/plane_multigrid.cpp is the CPU twin.
#extension GL_GOOGLE_include_directive : require
#include "sphere/texels.glsl"
#include "sphere/chebyshev.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D ad_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D b;
layout(binding = 3, rgba32ui) uniform writeonly uimage2D mix;

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint e = row.x; e < row.y; ++e) {
        const uvec4 entry = imageLoad(ad_entries, texel(e));
        sum += value_of(entry) * LOAD_VEC(b, entry.x);
    }
    const dvec2 bi = LOAD_VEC(b, i);
    STORE_VEC(mix, i, c0 * bi + c1 * (bi - theta_inverse * sum));
}

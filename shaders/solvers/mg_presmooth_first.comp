#version 460
// Multigrid V-cycle, on the way down, pass 1 of the Chebyshev smoother from zero: the first step
// x1 = D^-1 b / theta, its residual r1 = b - A x1, and what pass 2 needs of them,
// mix = c0 b + c1 r1 (the smoother's result is D^-1 mix). The entries come divided by their
// column's diagonal (a_ij / a_jj). In float, `precise` (no fused multiply-adds), as its CPU twin
// apply_multigrid_cpu in passes/solvers/multigrid.cpp rounds.
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"
#include "solvers/chebyshev.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rg32ui) uniform readonly uimage2D ad_entries;
layout(binding = 2, rg32f) uniform readonly image2D b;
layout(binding = 3, rg32f) uniform writeonly image2D mix;

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    precise vec2 sum = vec2(0.0);
    for (uint e = row.x; e < row.y; ++e) {
        const uvec2 entry = imageLoad(ad_entries, texel(e)).xy;
        sum += float_value_of(entry) * LOAD_VEC32(b, entry.x);
    }
    const vec2 bi = LOAD_VEC32(b, i);
    precise const vec2 m = c0 * bi + c1 * (bi - theta_inverse * sum);
    STORE_VEC32(mix, i, m);
}

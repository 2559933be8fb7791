#version 460
// Multigrid V-cycle, on the way down, pass 2 of the Chebyshev smoother from zero: its result
// x = D^-1 mix (mix = c0 b + c1 r1, from pass 1) and the residual r = b - A x, which the
// restriction takes down. The entries come divided by their column's diagonal (a_ij / a_jj); row
// i's texel holds 1 / a_ii. In float, `precise` (mg_presmooth_first says why).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"
#include "solvers/chebyshev.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rg32ui) uniform readonly uimage2D ad_entries;
layout(binding = 2, rg32f) uniform readonly image2D b;
layout(binding = 3, rg32f) uniform readonly image2D mix;
layout(binding = 4, rg32f) uniform writeonly image2D x;
layout(binding = 5, rg32f) uniform writeonly image2D r;

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    precise vec2 sum = vec2(0.0);
    for (uint e = row.x; e < row.y; ++e) {
        const uvec2 entry = imageLoad(ad_entries, texel(e)).xy;
        sum += float_value_of(entry) * LOAD_VEC32(mix, entry.x);
    }
    precise const vec2 xi = float(value_of(row)) * LOAD_VEC32(mix, i);
    precise const vec2 ri = LOAD_VEC32(b, i) - sum;
    STORE_VEC32(x, i, xi);
    STORE_VEC32(r, i, ri);
}

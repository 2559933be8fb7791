#version 460
// Multigrid V-cycle, on the way down, pass 2 of the Chebyshev smoother from zero: its result
// x = D^-1 mix (mix = c0 b + c1 r1, from pass 1) and the residual r = b - A x, which the
// restriction takes down. The entries come divided by their column's diagonal (a_ij / a_jj); row
// i's texel holds 1 / a_ii.
#extension GL_GOOGLE_include_directive : require
#include "sphere/texels.glsl"
#include "sphere/chebyshev.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D ad_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D b;
layout(binding = 3, rgba32ui) uniform readonly uimage2D mix;
layout(binding = 4, rgba32ui) uniform writeonly uimage2D x;
layout(binding = 5, rgba32ui) uniform writeonly uimage2D r;

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint e = row.x; e < row.y; ++e) {
        const uvec4 entry = imageLoad(ad_entries, texel(e));
        sum += value_of(entry) * LOAD_VEC(mix, entry.x);
    }
    STORE_VEC(x, i, value_of(row) * LOAD_VEC(mix, i));
    STORE_VEC(r, i, LOAD_VEC(b, i) - sum);
}

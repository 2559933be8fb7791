#version 460
// Multigrid V-cycle, on the way up, pass 1 of the Chebyshev smoother from x (after the coarse
// correction): x1 = x + D^-1 (b - A x) / theta. Row i's texel holds 1 / a_ii.
#extension GL_GOOGLE_include_directive : require
#include "sphere/texels.glsl"
#include "sphere/chebyshev.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D a_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D b;
layout(binding = 3, rgba32ui) uniform readonly uimage2D x;
layout(binding = 4, rgba32ui) uniform writeonly uimage2D x1;

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint e = row.x; e < row.y; ++e) {
        const uvec4 entry = imageLoad(a_entries, texel(e));
        sum += value_of(entry) * LOAD_VEC(x, entry.x);
    }
    STORE_VEC(x1, i, LOAD_VEC(x, i) + (theta_inverse * value_of(row)) * (LOAD_VEC(b, i) - sum));
}

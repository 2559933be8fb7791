#version 460
// Multigrid V-cycle, on the way up, pass 1 of the Chebyshev smoother from x (after the coarse
// correction): x1 = x + D^-1 (b - A x) / theta. Row i's texel holds 1 / a_ii. In float, `precise`
// (mg_presmooth_first says why).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"
#include "solvers/chebyshev.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rg32ui) uniform readonly uimage2D a_entries;
layout(binding = 2, rg32f) uniform readonly image2D b;
layout(binding = 3, rg32f) uniform readonly image2D x;
layout(binding = 4, rg32f) uniform writeonly image2D x1;

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    precise vec2 sum = vec2(0.0);
    for (uint e = row.x; e < row.y; ++e) {
        const uvec2 entry = imageLoad(a_entries, texel(e)).xy;
        sum += float_value_of(entry) * LOAD_VEC32(x, entry.x);
    }
    precise const vec2 x1i = LOAD_VEC32(x, i) + (theta_inverse * float(value_of(row))) * (LOAD_VEC32(b, i) - sum);
    STORE_VEC32(x1, i, x1i);
}

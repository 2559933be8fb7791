#version 460
// Multigrid V-cycle, on the way up, pass 2 of the Chebyshev smoother from x:
// z = x1 + k (x1 - x) + c1 D^-1 (b - A x1). Row i's texel holds 1 / a_ii. In float, `precise`
// (mg_presmooth_first says why). On the finest level (write_terms) it also writes row i's term of
// r . z in double for the conjugate gradients (b is their residual r, rounded to float, there).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"
#include "solvers/chebyshev.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rg32ui) uniform readonly uimage2D a_entries;
layout(binding = 2, rg32f) uniform readonly image2D b;
layout(binding = 3, rg32f) uniform readonly image2D x;
layout(binding = 4, rg32f) uniform readonly image2D x1;
layout(binding = 5, rg32f) uniform writeonly image2D z;
layout(std430, binding = 6) writeonly buffer Terms { double terms[]; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    precise vec2 sum = vec2(0.0);
    for (uint e = row.x; e < row.y; ++e) {
        const uvec2 entry = imageLoad(a_entries, texel(e)).xy;
        sum += float_value_of(entry) * LOAD_VEC32(x1, entry.x);
    }
    const vec2 bi = LOAD_VEC32(b, i);
    const vec2 x1i = LOAD_VEC32(x1, i);
    precise const vec2 zi = x1i + k * (x1i - LOAD_VEC32(x, i)) + (c1 * float(value_of(row))) * (bi - sum);
    STORE_VEC32(z, i, zi);
    if (write_terms != 0u) terms[i] = dot(dvec2(bi), dvec2(zi));
}

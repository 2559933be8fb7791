#version 460
// Multigrid V-cycle, on the way up, pass 2 of the Chebyshev smoother from x:
// z = x1 + k (x1 - x) + c1 D^-1 (b - A x1). Row i's texel holds 1 / a_ii. On the finest level
// (write_terms) it also writes row i's term of r . z for the conjugate gradients (b is their
// residual r there).
#extension GL_GOOGLE_include_directive : require
#include "sphere/texels.glsl"
#include "sphere/chebyshev.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D a_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D b;
layout(binding = 3, rgba32ui) uniform readonly uimage2D x;
layout(binding = 4, rgba32ui) uniform readonly uimage2D x1;
layout(binding = 5, rgba32ui) uniform writeonly uimage2D z;
layout(std430, binding = 6) writeonly buffer Terms { double terms[]; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint e = row.x; e < row.y; ++e) {
        const uvec4 entry = imageLoad(a_entries, texel(e));
        sum += value_of(entry) * LOAD_VEC(x1, entry.x);
    }
    const dvec2 bi = LOAD_VEC(b, i);
    const dvec2 x1i = LOAD_VEC(x1, i);
    const dvec2 zi = x1i + k * (x1i - LOAD_VEC(x, i)) + (c1 * value_of(row)) * (bi - sum);
    STORE_VEC(z, i, zi);
    if (write_terms != 0u) terms[i] = dot(bi, zi);
}

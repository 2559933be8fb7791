#version 460
// Multigrid V-cycle, on the way up: the last damped Jacobi step, z = x + S (b - A x); row i's
// texel holds s_i = omega / a_ii. On the finest level (write_terms) it also writes row i's term of
// r . z for the conjugate gradients (b is their residual r there).
#extension GL_GOOGLE_include_directive : require
#include "sphere/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D a_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D b;
layout(binding = 3, rgba32ui) uniform readonly uimage2D x;
layout(binding = 4, rgba32ui) uniform writeonly uimage2D z;
layout(std430, binding = 5) writeonly buffer Terms { double terms[]; };
layout(push_constant) uniform Push { uint rows; uint write_terms; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint k = row.x; k < row.y; ++k) {
        const uvec4 e = imageLoad(a_entries, texel(k));
        sum += value_of(e) * LOAD_VEC(x, e.x);
    }
    const dvec2 bi = LOAD_VEC(b, i);
    const dvec2 zi = LOAD_VEC(x, i) + value_of(row) * (bi - sum);
    STORE_VEC(z, i, zi);
    if (write_terms != 0u) terms[i] = dot(bi, zi);
}

#version 460
// BiCGSTAB, passes 2 and 4: out = A in (A in compressed rows, diagonal included), and the terms of
// two dot products per right-hand side for primitives/reduce_f64 (4 doubles a row):
// mode 0: (r0 . out) in terms 0-1; mode 1: (out . w) in 0-1 and (out . out) in 2-3.
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D a_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D in_vec;
layout(binding = 3, rgba32ui) uniform readonly uimage2D w;  // r0 (mode 0) or s (mode 1)
layout(binding = 4, rgba32ui) uniform writeonly uimage2D out_vec;
layout(std430, binding = 5) writeonly buffer Terms { double terms[]; };
layout(push_constant) uniform Push { uint rows; uint mode; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint k = row.x; k < row.y; ++k) {
        const uvec4 e = imageLoad(a_entries, texel(k));
        sum += value_of(e) * LOAD_VEC(in_vec, e.x);
    }
    STORE_VEC(out_vec, i, sum);
    const dvec2 wi = LOAD_VEC(w, i);
    terms[4 * i + 0] = wi.x * sum.x;
    terms[4 * i + 1] = wi.y * sum.y;
    terms[4 * i + 2] = mode == 1u ? sum.x * sum.x : 0.0LF;
    terms[4 * i + 3] = mode == 1u ? sum.y * sum.y : 0.0LF;
}

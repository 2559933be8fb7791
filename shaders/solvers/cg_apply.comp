#version 460
// Conjugate gradient of the planar polish, pass 1: q = A p for row i (A in compressed rows,
// diagonal included), and its term of p . q (summed by primitives/reduce_f64). cg_cpu in
// passes/solvers/conjugate_gradients.cpp is the CPU twin. Vectors and A are images (texels.glsl).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D p;
layout(binding = 1, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 2, rgba32ui) uniform readonly uimage2D a_entries;
layout(binding = 3, rgba32ui) uniform writeonly uimage2D q;
layout(std430, binding = 4) writeonly buffer Terms { double terms[]; };
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint k = row.x; k < row.y; ++k) {
        const uvec4 e = imageLoad(a_entries, texel(k));
        sum += value_of(e) * LOAD_VEC(p, e.x);
    }
    STORE_VEC(q, i, sum);
    terms[i] = dot(LOAD_VEC(p, i), sum);
}

#version 460
// Multigrid V-cycle of the planar polish, on the way down: the first damped Jacobi step from zero,
// x = S b, and its residual r = b - A x, in one pass. A neighbour's x is S b too, so the entries
// come pre-multiplied by their column's S (a_ij s_j); row i's texel holds s_i = omega / a_ii.
// apply_multigrid_cpu in passes/sphere/plane_multigrid.cpp is the CPU twin.
#extension GL_GOOGLE_include_directive : require
#include "sphere/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D as_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D b;
layout(binding = 3, rgba32ui) uniform writeonly uimage2D x;
layout(binding = 4, rgba32ui) uniform writeonly uimage2D r;
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(a_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint k = row.x; k < row.y; ++k) {
        const uvec4 e = imageLoad(as_entries, texel(k));
        sum += value_of(e) * LOAD_VEC(b, e.x);
    }
    const dvec2 bi = LOAD_VEC(b, i);
    STORE_VEC(x, i, value_of(row) * bi);
    STORE_VEC(r, i, bi - sum);
}

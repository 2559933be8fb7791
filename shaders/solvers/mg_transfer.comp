#version 460
// Multigrid V-cycle: a grid transfer, y = M v (restriction) or y += M v (prolongation), M in
// compressed rows with float entries. In float, `precise` (mg_presmooth_first says why).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D m_rows;
layout(binding = 1, rg32ui) uniform readonly uimage2D m_entries;
layout(binding = 2, rg32f) uniform readonly image2D v;
layout(binding = 3, rg32f) uniform image2D y;
layout(push_constant) uniform Push { uint rows; uint accumulate; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(m_rows, texel(i));
    precise vec2 sum = vec2(0.0);
    for (uint k = row.x; k < row.y; ++k) {
        const uvec2 e = imageLoad(m_entries, texel(k)).xy;
        sum += float_value_of(e) * LOAD_VEC32(v, e.x);
    }
    precise const vec2 yi = accumulate != 0u ? LOAD_VEC32(y, i) + sum : sum;
    STORE_VEC32(y, i, yi);
}

#version 460
// Multigrid V-cycle: a grid transfer, y = M v (restriction) or y += M v (prolongation), M in
// compressed rows.
#extension GL_GOOGLE_include_directive : require
#include "sphere/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D m_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D m_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D v;
layout(binding = 3, rgba32ui) uniform uimage2D y;
layout(push_constant) uniform Push { uint rows; uint accumulate; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const uvec4 row = imageLoad(m_rows, texel(i));
    dvec2 sum = dvec2(0.0LF);
    for (uint k = row.x; k < row.y; ++k) {
        const uvec4 e = imageLoad(m_entries, texel(k));
        sum += value_of(e) * LOAD_VEC(v, e.x);
    }
    STORE_VEC(y, i, accumulate != 0u ? LOAD_VEC(y, i) + sum : sum);
}

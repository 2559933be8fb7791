#version 460
// The predict step of the piecewise-linear wavelet transform on one level. The transform keeps
// two arrays: `coarse` the values being transformed, `detail` the details. Analysis
// detail[m] = coarse[m] - (coarse[a] + coarse[b]) / 2 for every odd vertex m with parent edge
// (a, b); synthesis coarse[m] = detail[m] + the same mean. The CPU twin's order of operations.
#extension GL_GOOGLE_include_directive : require
#include "maps/wavelet_values.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, r32ui) uniform uimage2D coarse;
layout(binding = 1, r32ui) uniform uimage2D detail;
layout(binding = 2, r32ui) uniform readonly uimage2D parents;  // 2 texels per odd vertex
layout(push_constant) uniform Push {
    uint first;    // the level's first odd vertex
    uint count;    // its odd vertices
    uint parent0;  // the parents entry of `first`
    uint inverse;  // 1: synthesis
};

void main() {
    const uint t = gl_GlobalInvocationID.x;
    if (t >= count) return;
    const uint m = first + t;
    const uvec2 p = uvec2(WORD_AT(parents, 2u * (parent0 + t)), WORD_AT(parents, 2u * (parent0 + t) + 1u));
    const dvec3 a = VALUE_AT(coarse, p.x), b = VALUE_AT(coarse, p.y);
    precise dvec3 mid = 0.5LF * (a + b);
    if (inverse != 0u) {
        precise dvec3 c = VALUE_AT(detail, m) + mid;
        STORE_VALUE(coarse, m, c)
    } else {
        precise dvec3 d = VALUE_AT(coarse, m) - mid;
        STORE_VALUE(detail, m, d)
    }
}

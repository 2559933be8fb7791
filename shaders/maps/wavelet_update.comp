#version 460
// The update step of the k-disk wavelet transform on one level (wavelet_predict.comp says what
// `coarse` and `detail` hold): analysis c_i + sum_m s_{i,m} d_m over the CSR row of even vertex
// i, synthesis c_i - the same sum, read from and written to `coarse`, or `detail` where the push
// constants say (the transform's last and first coarse values live there). The CPU twin's order
// of operations.
#extension GL_GOOGLE_include_directive : require
#include "maps/wavelet_values.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, r32ui) uniform uimage2D coarse;
layout(binding = 1, r32ui) uniform uimage2D detail;
layout(binding = 2, r32ui) uniform readonly uimage2D offsets;
layout(binding = 3, r32ui) uniform readonly uimage2D odd;
layout(binding = 4, r32ui) uniform readonly uimage2D weight;  // 2 texels per weight
layout(push_constant) uniform Push {
    uint count;        // even vertices: the coarse level's vertices
    uint offsets0;     // where the level's offsets begin
    uint entries0;     // where the level's odd ids and weights begin
    uint inverse;      // 1: synthesis
    uint from_detail;  // 1: c_i from `detail`
    uint to_detail;    // 1: the result to `detail`
};

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    const uint begin = WORD_AT(offsets, offsets0 + i), end = WORD_AT(offsets, offsets0 + i + 1u);
    precise dvec3 sum = dvec3(0.0LF);
    for (uint e = entries0 + begin; e < entries0 + end; ++e) sum += DOUBLE_AT(weight, e) * VALUE_AT(detail, WORD_AT(odd, e));
    const dvec3 c = from_detail != 0u ? VALUE_AT(detail, i) : VALUE_AT(coarse, i);
    precise dvec3 r = inverse != 0u ? c - sum : c + sum;
    if (to_detail != 0u) {
        STORE_VALUE(detail, i, r)
    } else {
        STORE_VALUE(coarse, i, r)
    }
}

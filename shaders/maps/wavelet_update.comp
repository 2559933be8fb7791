#version 460
// The update step of the k-disk wavelet transform on one level, in place: analysis
// c_i += sum_m s_{i,m} d_m over the CSR row of even vertex i, synthesis c_i -= the same sum, in
// the CPU twin's order of operations.
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Values { double values[]; };  // 3 per vertex
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 2) readonly buffer Odd { uint odd[]; };
layout(std430, binding = 3) readonly buffer Weight { double weight[]; };
layout(push_constant) uniform Push {
    uint count;     // even vertices: the coarse level's vertices
    uint offsets0;  // where the level's offsets begin
    uint entries0;  // where the level's odd ids and weights begin
    uint inverse;   // 1: synthesis
};

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    const uint begin = offsets[offsets0 + i], end = offsets[offsets0 + i + 1u];
    precise dvec3 sum = dvec3(0.0LF);
    for (uint e = entries0 + begin; e < entries0 + end; ++e) {
        const uint m = odd[e];
        sum += weight[e] * dvec3(values[3u * m], values[3u * m + 1u], values[3u * m + 2u]);
    }
    for (uint k = 0u; k < 3u; ++k) {
        precise double c = inverse != 0u ? values[3u * i + k] - sum[k] : values[3u * i + k] + sum[k];
        values[3u * i + k] = c;
    }
}

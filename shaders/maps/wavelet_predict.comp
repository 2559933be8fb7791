#version 460
// The predict step of the piecewise-linear wavelet transform on one level, in place: analysis
// d_m = c_m - (c_a + c_b) / 2 for every odd vertex m with parent edge (a, b), synthesis the
// inverse, in the CPU twin's order of operations.
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Values { double values[]; };            // 3 per vertex
layout(std430, binding = 1) readonly buffer Parents { uvec2 parents[]; };  // per odd vertex
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
    const uvec2 p = parents[parent0 + t];
    for (uint k = 0u; k < 3u; ++k) {
        precise double mid = 0.5LF * (values[3u * p.x + k] + values[3u * p.y + k]);
        precise double c = inverse != 0u ? values[3u * m + k] + mid : values[3u * m + k] - mid;
        values[3u * m + k] = c;
    }
}

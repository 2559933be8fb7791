#version 460
// Kuriyama & Kaneko's eq. (2) for the rows of one colour (no two of them neighbours, so the
// in-place update is the Gauss-Seidel sweep in colour order): x_i <- k x_i + (1 - k) sum_j w_ij x_j
// for one field (u or v), and the sweep's largest correction |sum_j w_ij x_j - x_i| (as float bits,
// which order like the values for non-negative floats) into its slot.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Rows { uint row_vertex[]; };
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 2) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 3) readonly buffer Weights { double weights[]; };
layout(std430, binding = 4) buffer Params { double uv[]; };  // (u, v) per vertex
layout(std430, binding = 5) buffer Slots { uint worst[]; };
layout(push_constant) uniform Push {
    uint first, count, field, sweep;
    double k;
};

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    const uint r = first + i, v = row_vertex[r];
    precise double mean = 0.0LF;
    for (uint e = offsets[r]; e < offsets[r + 1u]; ++e) mean += weights[e] * uv[2u * columns[e] + field];
    const double x = uv[2u * v + field];
    atomicMax(worst[sweep], floatBitsToUint(float(abs(mean - x))));
    precise double next = k * x + (1.0LF - k) * mean;
    uv[2u * v + field] = next;
}

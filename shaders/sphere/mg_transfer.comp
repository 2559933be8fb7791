#version 460
// Multigrid V-cycle: a grid transfer, y = M v (restriction) or y += M v (prolongation), M in
// compressed rows.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer Values { double values[]; };
layout(std430, binding = 3) readonly buffer V { dvec2 v[]; };
layout(std430, binding = 4) buffer Y { dvec2 y[]; };
layout(push_constant) uniform Push { uint rows; uint accumulate; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    dvec2 sum = dvec2(0.0LF);
    for (uint k = offsets[i]; k < offsets[i + 1]; ++k) sum += values[k] * v[columns[k]];
    y[i] = accumulate != 0u ? y[i] + sum : sum;
}

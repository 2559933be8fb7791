#version 460
// Multigrid V-cycle of the planar polish, on the way down: the first damped Jacobi step from zero,
// x = S b, and its residual r = b - A x, in one pass (a neighbour's x is S b too). S holds
// omega / a_ii. apply_multigrid_cpu in passes/sphere/plane_multigrid.cpp is the CPU twin.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer Values { double values[]; };
layout(std430, binding = 3) readonly buffer Smoother { double smoother[]; };
layout(std430, binding = 4) readonly buffer B { dvec2 b[]; };
layout(std430, binding = 5) writeonly buffer X { dvec2 x[]; };
layout(std430, binding = 6) writeonly buffer R { dvec2 r[]; };
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    dvec2 sum = dvec2(0.0LF);
    for (uint k = offsets[i]; k < offsets[i + 1]; ++k) {
        const uint j = columns[k];
        sum += values[k] * (smoother[j] * b[j]);
    }
    x[i] = smoother[i] * b[i];
    r[i] = b[i] - sum;
}

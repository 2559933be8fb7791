#version 460
// Multigrid V-cycle, on the way up: the last damped Jacobi step, z = x + S (b - A x). On the
// finest level (write_terms) it also writes row i's term of r . z for the conjugate gradients
// (b is their residual r there).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer Values { double values[]; };
layout(std430, binding = 3) readonly buffer Smoother { double smoother[]; };
layout(std430, binding = 4) readonly buffer B { dvec2 b[]; };
layout(std430, binding = 5) readonly buffer X { dvec2 x[]; };
layout(std430, binding = 6) writeonly buffer Z { dvec2 z[]; };
layout(std430, binding = 7) writeonly buffer Terms { double terms[]; };
layout(push_constant) uniform Push { uint rows; uint write_terms; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    dvec2 sum = dvec2(0.0LF);
    for (uint k = offsets[i]; k < offsets[i + 1]; ++k) sum += values[k] * x[columns[k]];
    const dvec2 zi = x[i] + smoother[i] * (b[i] - sum);
    z[i] = zi;
    if (write_terms != 0u) terms[i] = dot(b[i], zi);
}

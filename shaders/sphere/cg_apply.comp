#version 460
// Conjugate gradient of the planar polish, pass 1: q = A p for row i (A in compressed rows,
// diagonal included), and its term of p . q (summed by primitives/reduce_f64). plane_cg_cpu in
// passes/sphere/plane_cg.cpp is the CPU twin.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer P { dvec2 p[]; };
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 2) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 3) readonly buffer Values { double values[]; };
layout(std430, binding = 4) writeonly buffer Q { dvec2 q[]; };
layout(std430, binding = 5) writeonly buffer Terms { double terms[]; };
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    dvec2 sum = dvec2(0.0LF);
    for (uint k = offsets[i]; k < offsets[i + 1]; ++k) sum += values[k] * p[columns[k]];
    q[i] = sum;
    terms[i] = dot(p[i], sum);
}

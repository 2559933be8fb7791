#version 460
// Conjugate gradient, pass 2: alpha = r.z / p.q, x += alpha p, r -= alpha q. alpha is 0 when p.q
// is not positive (converged exactly).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer PQ { double pq; };
layout(std430, binding = 1) readonly buffer RZ { double rz; };
layout(std430, binding = 2) readonly buffer P { dvec2 p[]; };
layout(std430, binding = 3) readonly buffer Q { dvec2 q[]; };
layout(std430, binding = 4) buffer X { dvec2 x[]; };
layout(std430, binding = 5) buffer R { dvec2 r[]; };
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const double alpha = pq > 0.0LF ? rz / pq : 0.0LF;
    x[i] += alpha * p[i];
    r[i] -= alpha * q[i];
}

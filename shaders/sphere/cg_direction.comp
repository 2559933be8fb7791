#version 460
// Conjugate gradient, pass 3 (after the multigrid cycle z = M r and r.z): p = z + beta p,
// beta = (new r.z) / (old r.z).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer OldRZ { double rz_old; };
layout(std430, binding = 1) readonly buffer NewRZ { double rz_new; };
layout(std430, binding = 2) readonly buffer Z { dvec2 z[]; };
layout(std430, binding = 3) buffer P { dvec2 p[]; };
layout(push_constant) uniform Push { uint rows; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= rows) return;
    const double beta = rz_old > 0.0LF ? rz_new / rz_old : 0.0LF;
    p[i] = z[i] + beta * p[i];
}

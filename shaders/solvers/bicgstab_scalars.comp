#version 460
// BiCGSTAB's scalars, one thread (passes/solvers/bicgstab.cpp; bicgstab_cpu is the CPU twin), per
// right-hand side of the pair: step 0 after r0.r: beta = (rho' / rho) (alpha / omega), rho = rho';
// step 1 after r0.v: alpha = rho / (r0.v); step 2 after t.s and t.t: omega = (t.s) / (t.t). A
// vanishing denominator makes the step 0 (the host then reports the breakdown).
#extension GL_GOOGLE_include_directive : require
#include "solvers/bicgstab_scalars.glsl"

layout(local_size_x = 1) in;
layout(std430, binding = 0) buffer Scalars { BicgScalars s; };
layout(std430, binding = 1) readonly buffer Sums { double sums[4]; };
layout(push_constant) uniform Push { uint step; };

void main() {
    for (int c = 0; c < 2; ++c) {
        if (step == 0u) {
            const double rho_new = sums[c];
            s.beta[c] = s.rho[c] != 0.0LF && s.omega[c] != 0.0LF ? (rho_new / s.rho[c]) * (s.alpha[c] / s.omega[c]) : 0.0LF;
            s.rho[c] = rho_new;
        } else if (step == 1u) {
            s.alpha[c] = sums[c] != 0.0LF ? s.rho[c] / sums[c] : 0.0LF;
        } else {
            s.omega[c] = sums[2 + c] > 0.0LF ? sums[c] / sums[2 + c] : 0.0LF;
        }
    }
}

#version 460
// BiCGSTAB's dot products finished and its scalars, one workgroup (passes/solvers/bicgstab.cpp;
// bicgstab_cpu is the CPU twin): the workgroups' sums of the pass before (workgroup_sums.glsl),
// added in a fixed order, give sums 0-3, then per right-hand side of the pair:
//   step 0 after the update, sums (r0.r, r.r): beta = (rho' / rho) (alpha / omega) and rho = rho'
//          for the next iteration, and the sums for the host (its convergence check);
//   step 1 after v = A y, sums (r0.v): alpha = rho / (r0.v);
//   step 2 after t = A z, sums (t.s, t.t): omega = (t.s) / (t.t).
// A vanishing denominator makes the step 0 (the host then reports the breakdown).
#extension GL_GOOGLE_include_directive : require
#include "solvers/bicgstab_scalars.glsl"

const uint kThreads = 64u;

layout(local_size_x = kThreads) in;
layout(std430, binding = 0) buffer Scalars { BicgScalars s; };
layout(std430, binding = 1) readonly buffer Partials { double partials[]; };
layout(std430, binding = 2) writeonly buffer Sums { double sums_out[4]; };
layout(push_constant) uniform Push { uint groups; uint step; };

shared dvec4 thread_sums[kThreads];

void main() {
    const uint lid = gl_LocalInvocationID.x;
    dvec4 sum = dvec4(0.0LF);
    for (uint g = lid; g < groups; g += kThreads)
        sum += dvec4(partials[4u * g], partials[4u * g + 1u], partials[4u * g + 2u], partials[4u * g + 3u]);
    thread_sums[lid] = sum;
    barrier();
    if (lid != 0u) return;
    dvec4 sums = thread_sums[0];
    for (uint k = 1u; k < kThreads; ++k) sums += thread_sums[k];
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
    if (step == 0u)
        for (uint c = 0u; c < 4u; ++c) sums_out[c] = sums[c];
}

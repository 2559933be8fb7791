// Per-workgroup sums of four doubles for BiCGSTAB's dot products: the invocations' terms go to
// shared memory and invocation 0 adds them in order, so every run on one device gives the same
// bits. One barrier and no subgroup arithmetic. bicgstab_finish adds the workgroups' sums. The
// including shader has local_size_x = kSumThreads and declares `double partials[]` (4 a workgroup).
#ifndef GIMG_WORKGROUP_SUMS_GLSL
#define GIMG_WORKGROUP_SUMS_GLSL
const uint kSumThreads = 64u;

shared dvec4 workgroup_terms[kSumThreads];

// Called by every invocation of the workgroup (rows past the end with zero terms): it has a barrier.
void write_workgroup_sums(dvec4 terms) {
    workgroup_terms[gl_LocalInvocationID.x] = terms;
    barrier();
    if (gl_LocalInvocationID.x == 0u) {
        dvec4 sum = workgroup_terms[0];
        for (uint k = 1u; k < kSumThreads; ++k) sum += workgroup_terms[k];
        for (uint c = 0u; c < 4u; ++c) partials[4u * gl_WorkGroupID.x + c] = sum[c];
    }
}
#endif

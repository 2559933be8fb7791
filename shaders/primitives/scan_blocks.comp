#version 460
// Inclusive prefix sum within blocks of GIMG_SCAN_BLOCK elements; each block's total goes to
// block_sums so a second level can scan them.
#extension GL_GOOGLE_include_directive : require
#include "primitives/scan_config.h"

layout(local_size_x = GIMG_SCAN_THREADS) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { uint dst[]; };
layout(std430, binding = 2) writeonly buffer BlockSums { uint block_sums[]; };
layout(push_constant) uniform Push { uint count; };

shared uint thread_sums[GIMG_SCAN_THREADS];

void main() {
    const uint lid = gl_LocalInvocationID.x;
    const uint base = gl_WorkGroupID.x * GIMG_SCAN_BLOCK + lid * GIMG_SCAN_PER_THREAD;
    uint running[GIMG_SCAN_PER_THREAD];
    uint sum = 0;
    for (uint k = 0; k < GIMG_SCAN_PER_THREAD; ++k) {
        const uint i = base + k;
        sum += i < count ? src[i] : 0u;
        running[k] = sum;
    }
    thread_sums[lid] = sum;
    barrier();
    // Hillis-Steele inclusive scan of the per-thread sums.
    for (uint offset = 1; offset < GIMG_SCAN_THREADS; offset <<= 1) {
        const uint add = lid >= offset ? thread_sums[lid - offset] : 0u;
        barrier();
        thread_sums[lid] += add;
        barrier();
    }
    const uint before = lid > 0 ? thread_sums[lid - 1] : 0u;
    for (uint k = 0; k < GIMG_SCAN_PER_THREAD; ++k) {
        const uint i = base + k;
        if (i < count) dst[i] = running[k] + before;
    }
    if (lid == GIMG_SCAN_THREADS - 1) block_sums[gl_WorkGroupID.x] = thread_sums[lid];
}

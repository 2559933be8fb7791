#version 460
// Sum of GIMG_SCAN_BLOCK elements per workgroup by a fixed shared-memory tree, so the result is
// the same on every run (float atomics would not be).
#extension GL_GOOGLE_include_directive : require
#include "primitives/scan_config.h"

layout(local_size_x = GIMG_SCAN_THREADS) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Partial { uint partial[]; };
layout(push_constant) uniform Push { uint count; };

shared uint sums[GIMG_SCAN_THREADS];

void main() {
    const uint lid = gl_LocalInvocationID.x;
    const uint base = gl_WorkGroupID.x * GIMG_SCAN_BLOCK + lid;
    uint sum = 0;
    for (uint k = 0; k < GIMG_SCAN_PER_THREAD; ++k) {
        const uint i = base + k * GIMG_SCAN_THREADS;  // strided: neighbouring invocations read neighbours
        sum += i < count ? src[i] : 0u;
    }
    sums[lid] = sum;
    barrier();
    for (uint stride = GIMG_SCAN_THREADS / 2; stride > 0; stride >>= 1) {
        if (lid < stride) sums[lid] += sums[lid + stride];
        barrier();
    }
    if (lid == 0) partial[gl_WorkGroupID.x] = sums[0];
}

#version 460
// Sums of `width` interleaved double components (e.g. x, y, z of points) over GIMG_SCAN_BLOCK
// elements per workgroup, by a fixed shared-memory tree: the same result on every run.
#extension GL_GOOGLE_include_directive : require
#include "primitives/scan_config.h"

layout(local_size_x = GIMG_SCAN_THREADS) in;
layout(std430, binding = 0) readonly buffer Src { double src[]; };
layout(std430, binding = 1) writeonly buffer Partial { double partial[]; };
layout(push_constant) uniform Push { uint count; uint width; };

shared double sums[GIMG_SCAN_THREADS];

void main() {
    const uint lid = gl_LocalInvocationID.x;
    const uint base = gl_WorkGroupID.x * GIMG_SCAN_BLOCK + lid;
    for (uint c = 0; c < width; ++c) {
        double sum = 0.0LF;
        for (uint k = 0; k < GIMG_SCAN_PER_THREAD; ++k) {
            const uint i = base + k * GIMG_SCAN_THREADS;
            sum += i < count ? src[i * width + c] : 0.0LF;
        }
        sums[lid] = sum;
        barrier();
        for (uint stride = GIMG_SCAN_THREADS / 2; stride > 0; stride >>= 1) {
            if (lid < stride) sums[lid] += sums[lid + stride];
            barrier();
        }
        if (lid == 0) partial[gl_WorkGroupID.x * width + c] = sums[0];
        barrier();
    }
}

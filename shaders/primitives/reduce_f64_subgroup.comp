#version 460
// reduce_f64.comp's sums by subgroup arithmetic instead of a shared-memory tree, on devices that
// have it: workgroups of 8 invocations, each summing every 8th of the workgroup's GIMG_SCAN_BLOCK
// elements, then subgroupAdd, then the subgroups' sums in order (one subgroup wherever the
// subgroup size is 8 or more). On lavapipe the tree's nine workgroup barriers made a reduction of
// 104K doubles cost 0.85-1.0 ms; this costs 0.25-0.3 ms. The order of the additions is fixed by
// the compiled shader, so every run on one device gives the same bits.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "primitives/scan_config.h"

const uint kThreads = 8u;

layout(local_size_x = kThreads) in;
layout(std430, binding = 0) readonly buffer Src { double src[]; };
layout(std430, binding = 1) writeonly buffer Partial { double partial[]; };
layout(push_constant) uniform Push { uint count; uint width; };

shared double subgroup_sums[kThreads];

void main() {
    const uint lid = gl_LocalInvocationID.x;
    const uint base = gl_WorkGroupID.x * GIMG_SCAN_BLOCK + lid;
    for (uint c = 0; c < width; ++c) {
        double sum = 0.0LF;
        for (uint k = 0; k < GIMG_SCAN_BLOCK / kThreads; ++k) {
            const uint i = base + k * kThreads;
            sum += i < count ? src[i * width + c] : 0.0LF;
        }
        sum = subgroupAdd(sum);
        if (subgroupElect()) subgroup_sums[gl_SubgroupID] = sum;
        barrier();
        if (lid == 0) {
            double total = 0.0LF;
            for (uint s = 0; s < gl_NumSubgroups; ++s) total += subgroup_sums[s];
            partial[gl_WorkGroupID.x * width + c] = total;
        }
        barrier();
    }
}

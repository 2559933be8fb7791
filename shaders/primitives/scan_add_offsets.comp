#version 460
// Second half of a multi-level scan: add the inclusive scan of the earlier blocks' totals.
#extension GL_GOOGLE_include_directive : require
#include "primitives/scan_config.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) buffer Data { uint data[]; };
layout(std430, binding = 1) readonly buffer ScannedBlockSums { uint scanned[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    const uint block = i / GIMG_SCAN_BLOCK;
    if (i < count && block > 0) data[i] += scanned[block - 1];
}

#version 460
// Reconstruction, step 3: compaction - each valid pixel's point to its place in the vertex list
// (the inclusive prefix sum of the valid flags, minus one).
#extension GL_GOOGLE_include_directive : require
#include "reconstruct/reconstruct_common.h"

layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 1) readonly buffer VertexIndex { uint vertex_index[]; };
layout(std430, binding = 2) writeonly buffer Out { float positions[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= count || points[i].w == 0.0) return;
    const uint o = vertex_index[i] - 1u;
    positions[3 * o] = points[i].x;
    positions[3 * o + 1] = points[i].y;
    positions[3 * o + 2] = points[i].z;
}

#version 460
// Reconstruction, step 1 for position images: the stored position (NaN x: empty).
#extension GL_GOOGLE_include_directive : require
#include "reconstruct/reconstruct_common.h"

layout(local_size_x = GIMG_RECON_GROUP, local_size_y = GIMG_RECON_GROUP) in;
layout(std430, binding = 0) readonly buffer Xyz { float xyz[]; };
layout(std430, binding = 1) writeonly buffer Points { vec4 points[]; };
layout(std430, binding = 2) writeonly buffer Valid { uint valid[]; };
layout(push_constant) uniform Push { uint width; uint height; };

void main() {
    const uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= width || p.y >= height) return;
    const uint i = p.y * width + p.x;
    const vec3 q = vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    const bool ok = !isnan(q.x);
    points[i] = ok ? vec4(q, 1.0) : vec4(0.0);
    valid[i] = ok ? 1u : 0u;
}

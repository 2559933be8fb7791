#version 460
// Reconstruction, step 2: per 2x2 block, 2 triangles when all four pixels are valid and the
// block's jump is within the threshold (cylindrical: max d - min d; positions: the largest
// squared 3D distance against threshold^2), else 0.
#extension GL_GOOGLE_include_directive : require
#include "reconstruct/reconstruct_common.h"

layout(local_size_x = GIMG_RECON_GROUP, local_size_y = GIMG_RECON_GROUP) in;
layout(std430, binding = 0) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 1) readonly buffer Distance { float d[]; };
layout(std430, binding = 2) writeonly buffer Counts { uint counts[]; };
layout(push_constant) uniform Push { uint width; uint height; uint wrap; uint cylindrical; float threshold; };

void main() {
    const uint blocks_per_row = wrap != 0u ? width : width - 1u;
    const uvec2 b = gl_GlobalInvocationID.xy;
    if (b.x >= blocks_per_row || b.y + 1u >= height) return;
    uint c[4];
    block_corners(b.x, b.y, width, c);
    uint count = 0u;
    if (points[c[0]].w != 0.0 && points[c[1]].w != 0.0 && points[c[2]].w != 0.0 && points[c[3]].w != 0.0) {
        bool ok;
        if (cylindrical != 0u) {
            double lo = double(d[c[0]]), hi = lo;
            for (int k = 1; k < 4; ++k) lo = min(lo, double(d[c[k]])), hi = max(hi, double(d[c[k]]));
            ok = hi - lo <= double(threshold);
        } else {
            double worst = 0.0LF;
            for (int a = 0; a < 4; ++a)
                for (int k = a + 1; k < 4; ++k) worst = max(worst, squared_distance(points[c[a]], points[c[k]]));
            ok = worst <= double(threshold) * double(threshold);
        }
        count = ok ? 2u : 0u;
    }
    counts[b.y * blocks_per_row + b.x] = count;
}

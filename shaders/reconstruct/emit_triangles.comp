#version 460
// Reconstruction, step 4: each kept block's two triangles, cut along the shorter diagonal (a-d on
// ties), wound to face the wall they are seen from (cylindrical: the sign of the four d summed)
// or against +s x +t (position images), at the block's place in the triangle list.
#extension GL_GOOGLE_include_directive : require
#include "reconstruct/reconstruct_common.h"

layout(local_size_x = GIMG_RECON_GROUP, local_size_y = GIMG_RECON_GROUP) in;
layout(std430, binding = 0) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 1) readonly buffer Distance { float d[]; };
layout(std430, binding = 2) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 3) readonly buffer TriangleEnd { uint triangle_end[]; };  // inclusive sums
layout(std430, binding = 4) readonly buffer VertexIndex { uint vertex_index[]; };
layout(std430, binding = 5) writeonly buffer Out { uint triangles[]; };
layout(push_constant) uniform Push { uint width; uint height; uint wrap; uint cylindrical; };

void main() {
    const uint blocks_per_row = wrap != 0u ? width : width - 1u;
    const uvec2 b = gl_GlobalInvocationID.xy;
    if (b.x >= blocks_per_row || b.y + 1u >= height) return;
    const uint block = b.y * blocks_per_row + b.x;
    if (counts[block] == 0u) return;
    uint c[4];
    block_corners(b.x, b.y, width, c);
    const bool ad = squared_distance(points[c[0]], points[c[3]]) <= squared_distance(points[c[1]], points[c[2]]);
    bool faces_plus = false;
    if (cylindrical != 0u)
        faces_plus = (double(d[c[0]]) + double(d[c[1]])) + (double(d[c[2]]) + double(d[c[3]])) >= 0.0LF;
    uint t[6] = ad ? uint[6](0, 1, 3, 0, 3, 2) : uint[6](0, 1, 2, 1, 3, 2);
    if (!faces_plus) {
        uint s = t[1]; t[1] = t[2]; t[2] = s;
        s = t[4]; t[4] = t[5]; t[5] = s;
    }
    const uint first = triangle_end[block] - 2u;  // in triangles
    for (uint k = 0; k < 6u; ++k) triangles[3u * first + k] = vertex_index[c[t[k]]] - 1u;
}

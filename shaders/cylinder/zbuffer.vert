#version 460
// Cylindrical Z-buffer, step 2: each rectangle from the classify pass becomes a screen-space quad
// over its pixels in the image's tile of the atlas (6 vertices, no vertex buffers).
#extension GL_GOOGLE_include_directive : require
#include "cylinder/cylinder_layout.h"
#include "cylinder/cylinder_job.h"

layout(std430, binding = 0) readonly buffer Rects { uvec4 rects[]; };
layout(std430, binding = 1) readonly buffer Jobs { CylinderJob jobs[]; };
layout(push_constant) uniform Push { vec2 atlas_size; };

layout(location = 0) flat out uint face;
layout(location = 1) flat out uint job;

void main() {
    const uvec4 r = rects[gl_VertexIndex / 6];
    const uint corner = gl_VertexIndex % 6;
    // Two triangles: (0,0) (1,0) (1,1) and (0,0) (1,1) (0,1).
    const uvec2 c = corner == 0 || corner == 3 ? uvec2(0, 0)
                  : corner == 1                ? uvec2(1, 0)
                  : corner == 2 || corner == 4 ? uvec2(1, 1)
                                               : uvec2(0, 1);
    const CylinderJob jb = jobs[r.y];
    const vec2 lo = vec2(r.z & 0xffffu, r.w & 0xffffu), hi = vec2(r.z >> 16, r.w >> 16) + 1.0;
    const vec2 pixel = vec2(jb.tile_x, jb.tile_y) + mix(lo, hi, vec2(c));
    gl_Position = vec4(pixel / atlas_size * 2.0 - 1.0, 0.5, 1.0);
    face = r.x;
    job = r.y;
}

#version 460
// Cylindrical Z-buffer, step 2: each rectangle from the classify pass becomes one screen-space
// triangle covering its pixels in the image's tile of the atlas: (lo), (lo + 2 size.x, lo),
// (lo, lo + 2 size.y). Three vertices instead of a quad's six halve the vertex work, which is what
// a CPU rasteriser spends most of its time on; the fragment stage drops pixels outside the rectangle.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/cylinder_layout.h"
#include "cylinder/cylinder_job.h"

layout(std430, binding = 0) readonly buffer Rects { uvec4 rects[]; };
layout(std430, binding = 1) readonly buffer Jobs { CylinderJob jobs[]; };
layout(push_constant) uniform Push { vec2 atlas_size; };

layout(location = 0) flat out uint face;
layout(location = 1) flat out uint job;
layout(location = 2) flat out uvec2 rect_lo;  // the rectangle's pixels: [lo, hi) in the atlas
layout(location = 3) flat out uvec2 rect_hi;

void main() {
    const uvec4 r = rects[gl_VertexIndex / 3];
    const uint corner = gl_VertexIndex % 3;
    const CylinderJob jb = jobs[r.y];
    const vec2 tile = vec2(jb.tile_x, jb.tile_y);
    const vec2 lo = tile + vec2(r.z & 0xffffu, r.w & 0xffffu), hi = tile + vec2(r.z >> 16, r.w >> 16) + 1.0;
    const vec2 pixel = corner == 0 ? lo : (corner == 1 ? vec2(2.0 * hi.x - lo.x, lo.y) : vec2(lo.x, 2.0 * hi.y - lo.y));
    gl_Position = vec4(pixel / atlas_size * 2.0 - 1.0, 0.5, 1.0);
    face = r.x;
    job = r.y;
    rect_lo = uvec2(lo);
    rect_hi = uvec2(hi);
}

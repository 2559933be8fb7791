// Cylindrical Z-buffer, step 3: this pixel against the piece's triangle (line_hit.glsl); the
// depth test keeps the largest t. Included by zbuffer.frag (double precision) and
// zbuffer_float.frag (float), with REAL, REAL2, REAL3, REAL4 defined.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/cylinder_layout.h"
#include "cylinder/cylinder_job.h"
#include "common/texel_array.glsl"

layout(std430, binding = 1) readonly buffer Jobs { CylinderJob jobs[]; };
layout(binding = 2, rgba32f) uniform readonly image2D positions;
layout(binding = 3, rgba32ui) uniform readonly uimage2D triangles;
layout(binding = 4, rgba32ui) uniform readonly uimage2D directions;
layout(push_constant) uniform Push { vec2 atlas_size; uvec2 image_size; };

layout(location = 0) flat in uint face;
layout(location = 1) flat in uint job;
layout(location = 2) flat in uvec2 rect_lo;
layout(location = 3) flat in uvec2 rect_hi;
layout(location = 0) out float distance;

#include "cylinder/line_hit.glsl"

void main() {
    const uvec2 atlas_pixel = uvec2(gl_FragCoord.xy);
    if (any(lessThan(atlas_pixel, rect_lo)) || any(greaterThanEqual(atlas_pixel, rect_hi))) discard;
    const CylinderJob jb = jobs[job];
    const uvec4 corners = imageLoad(triangles, texel(face));
    const REAL3 a = cylinder_point(jb, model_corner(jb, corners, 0));
    REAL t;
    if (!line_hit(a, cylinder_point(jb, model_corner(jb, corners, 1)), cylinder_point(jb, model_corner(jb, corners, 2)),
                  atlas_pixel - uvec2(jb.tile_x, jb.tile_y), image_size.y, t)) discard;
    distance = float(t);
    gl_FragDepth = float(REAL(0.5) * (REAL(1.0) - t));
}

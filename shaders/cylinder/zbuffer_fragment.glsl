// Cylindrical Z-buffer, step 3: intersect this pixel's line - perpendicular to the axis at y_v in
// direction theta_u, walked from the wall (t = 1) through the axis to t = -1 - with the triangle,
// using the ray caster's own test (Moller-Trumbore, no epsilon) and its own tabulated directions.
// Keep the hit if the triangle faces the wall the line starts from; the depth test keeps the
// largest t. Included by zbuffer.frag (double precision) and zbuffer_float.frag (float), with
// REAL, REAL2, REAL3, REAL4 defined.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/cylinder_layout.h"
#include "cylinder/cylinder_job.h"

layout(std430, binding = 1) readonly buffer Jobs { CylinderJob jobs[]; };
layout(std430, binding = 2) readonly buffer Positions { float positions[]; };
layout(std430, binding = 3) readonly buffer Triangles { uint triangles[]; };
layout(std430, binding = 4) readonly buffer Directions { REAL2 directions[]; };  // (cos, sin) of theta_u
layout(push_constant) uniform Push { vec2 atlas_size; uvec2 image_size; };

layout(location = 0) flat in uint face;
layout(location = 1) flat in uint job;
layout(location = 2) flat in uvec2 rect_lo;
layout(location = 3) flat in uvec2 rect_hi;
layout(location = 0) out float distance;

REAL3 vertex(const CylinderJob jb, uint k) {
    const uint idx = jb.vertex_offset + triangles[3 * face + k];
    const REAL4 p = REAL4(positions[3 * idx], positions[3 * idx + 1], positions[3 * idx + 2], 1.0);
    return REAL3(dot(REAL4(jb.rows[0]), p), dot(REAL4(jb.rows[1]), p), dot(REAL4(jb.rows[2]), p));
}

void main() {
    const uvec2 atlas_pixel = uvec2(gl_FragCoord.xy);
    if (any(lessThan(atlas_pixel, rect_lo)) || any(greaterThanEqual(atlas_pixel, rect_hi))) discard;
    const CylinderJob jb = jobs[job];
    const uvec2 pixel = atlas_pixel - uvec2(jb.tile_x, jb.tile_y);
    const REAL y = REAL(1.0) - (REAL(pixel.y) + REAL(0.5)) / REAL(image_size.y);
    const REAL2 cs = directions[pixel.x];
    const REAL3 dir = REAL3(cs.x, 0.0, cs.y);
    const REAL3 a = vertex(jb, 0), e1 = vertex(jb, 1) - a, e2 = vertex(jb, 2) - a;
    // Facing the starting wall: the normal has a positive component along the line's direction.
    if (dot(cross(e1, e2), dir) <= REAL(0.0)) discard;
    // Moller-Trumbore for origin o = (0, y, 0) and direction dir.
    const REAL3 pvec = cross(dir, e2);
    const REAL inv = REAL(1.0) / dot(e1, pvec);
    const REAL3 tvec = REAL3(0.0, y, 0.0) - a;
    const REAL u = dot(tvec, pvec) * inv;
    if (u < REAL(0.0) || u > REAL(1.0)) discard;
    const REAL3 qvec = cross(tvec, e1);
    const REAL v = dot(dir, qvec) * inv;
    if (v < REAL(0.0) || u + v > REAL(1.0)) discard;
    const REAL t = dot(e2, qvec) * inv;
    if (t < REAL(-1.0) || t > REAL(1.0)) discard;
    distance = float(t);
    gl_FragDepth = float(REAL(0.5) * (REAL(1.0) - t));
}

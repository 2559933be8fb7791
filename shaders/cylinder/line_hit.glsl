// The exact test of the cylindrical Z-buffer, shared by the fragment stage (large pieces) and
// the classify pass (small pieces, rasterised in compute) so that both decide every pixel alike:
// intersect pixel (u, v)'s line - perpendicular to the axis at y_v in direction theta_u, walked
// from the wall (t = 1) through the axis to t = -1 - with the triangle, using the ray caster's own
// test (Moller-Trumbore, no epsilon) and its own tabulated directions. A hit counts only if the
// triangle faces the wall the line starts from. The includer declares the images positions and
// triangles (common/texel_array.glsl: texel v holds (x, y, z, 0), texel f a face's three corners)
// and directions (texel u: cos and sin of theta_u as REAL bits), and defines REAL, REAL2, REAL3,
// REAL4 and REAL2_OF_TEXEL.
//
// In double precision that is the ray caster's test exactly. In single precision (LINE_HIT_WATERTIGHT,
// set by the float shaders) Moller-Trumbore can let a line through an edge two triangles share miss
// both, depending on how the driver contracts products into FMAs (seen on NVIDIA, not on lavapipe).
// The float test therefore decides by one signed volume per edge, computed from the edge's two
// corners alone and without contraction (precise), so the two triangles get exactly opposite values
// and a line through their edge hits both; the depth test keeps one.
#ifndef LINE_HIT_WATERTIGHT
#define LINE_HIT_WATERTIGHT 0
#endif

#if LINE_HIT_WATERTIGHT
// A model-space point in the cylinder frame, every product rounded alike in every shader.
REAL3 cylinder_point(const CylinderJob jb, vec3 model) {
    precise REAL3 r;
    for (int k = 0; k < 3; ++k)
        r[k] = REAL(jb.rows[k].x) * model.x + REAL(jb.rows[k].y) * model.y + REAL(jb.rows[k].z) * model.z + REAL(jb.rows[k].w);
    return r;
}
#else
// A model-space point in the cylinder frame, in REAL precision.
REAL3 cylinder_point(const CylinderJob jb, vec3 model) {
    const REAL4 p = REAL4(model, 1.0);
    return REAL3(dot(REAL4(jb.rows[0]), p), dot(REAL4(jb.rows[1]), p), dot(REAL4(jb.rows[2]), p));
}
#endif

// Corner k of a face, given the face's texel of triangles, in model space.
vec3 model_corner(const CylinderJob jb, uvec4 corners, uint k) {
    return imageLoad(positions, texel(jb.vertex_offset + corners[k])).xyz;
}

#if LINE_HIT_WATERTIGHT
// The volume spanned by the line's direction and the corners p, q (relative to the line's origin):
// edge_volume(q, p) is exactly -edge_volume(p, q).
REAL edge_volume(REAL3 p, REAL3 q, REAL3 dir) {
    precise REAL v = dir.x * (p.y * q.z - p.z * q.y) + dir.y * (p.z * q.x - p.x * q.z) + dir.z * (p.x * q.y - p.y * q.x);
    return v;
}

// The triangle a, b, c against pixel (u, v) of an image `height` rows high.
bool line_hit(REAL3 a, REAL3 b, REAL3 c, uvec2 pixel, uint height, out REAL t) {
    t = REAL(0.0);
    precise const REAL y = REAL(1.0) - (REAL(pixel.y) + REAL(0.5)) / REAL(height);
    const REAL2 cs = REAL2_OF_TEXEL(imageLoad(directions, texel(pixel.x)));
    const REAL3 dir = REAL3(cs.x, 0.0, cs.y);
    precise const REAL3 pa = a - REAL3(0.0, y, 0.0), pb = b - REAL3(0.0, y, 0.0), pc = c - REAL3(0.0, y, 0.0);
    const REAL wa = edge_volume(pb, pc, dir), wb = edge_volume(pc, pa, dir), wc = edge_volume(pa, pb, dir);
    const REAL sum = wa + wb + wc;  // the triangle's normal along the line: positive when it faces the wall
    if (sum <= REAL(0.0) || wa < REAL(0.0) || wb < REAL(0.0) || wc < REAL(0.0)) return false;
    t = dot((wa * pa + wb * pb + wc * pc) / sum, dir);
    return t >= REAL(-1.0) && t <= REAL(1.0);
}
#else
// The triangle a, b, c against pixel (u, v) of an image `height` rows high.
bool line_hit(REAL3 a, REAL3 b, REAL3 c, uvec2 pixel, uint height, out REAL t) {
    const REAL3 e1 = b - a, e2 = c - a;
    t = REAL(0.0);
    const REAL y = REAL(1.0) - (REAL(pixel.y) + REAL(0.5)) / REAL(height);
    const REAL2 cs = REAL2_OF_TEXEL(imageLoad(directions, texel(pixel.x)));
    const REAL3 dir = REAL3(cs.x, 0.0, cs.y);
    // Facing the starting wall: the normal has a positive component along the line's direction.
    if (dot(cross(e1, e2), dir) <= REAL(0.0)) return false;
    // Moller-Trumbore for origin o = (0, y, 0) and direction dir.
    const REAL3 pvec = cross(dir, e2);
    const REAL inv = REAL(1.0) / dot(e1, pvec);
    const REAL3 tvec = REAL3(0.0, y, 0.0) - a;
    const REAL u = dot(tvec, pvec) * inv;
    if (u < REAL(0.0) || u > REAL(1.0)) return false;
    const REAL3 qvec = cross(tvec, e1);
    const REAL v = dot(dir, qvec) * inv;
    if (v < REAL(0.0) || u + v > REAL(1.0)) return false;
    t = dot(e2, qvec) * inv;
    return t >= REAL(-1.0) && t <= REAL(1.0);
}
#endif

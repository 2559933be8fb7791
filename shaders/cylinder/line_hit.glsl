// The exact test of the cylindrical Z-buffer, shared by the fragment stage (large pieces) and
// the classify pass (small pieces, rasterised in compute) so that both decide every pixel alike:
// intersect pixel (u, v)'s line - perpendicular to the axis at y_v in direction theta_u, walked
// from the wall (t = 1) through the axis to t = -1 - with the triangle, using the ray caster's own
// test (Moller-Trumbore, no epsilon) and its own tabulated directions. A hit counts only if the
// triangle faces the wall the line starts from. The includer declares the images positions and
// triangles (common/texel_array.glsl: texel v holds (x, y, z, 0), texel f a face's three corners)
// and directions (texel u: cos and sin of theta_u as REAL bits), and defines REAL, REAL2, REAL3,
// REAL4 and REAL2_OF_TEXEL.

// A model-space point in the cylinder frame, in REAL precision.
REAL3 cylinder_point(const CylinderJob jb, vec3 model) {
    const REAL4 p = REAL4(model, 1.0);
    return REAL3(dot(REAL4(jb.rows[0]), p), dot(REAL4(jb.rows[1]), p), dot(REAL4(jb.rows[2]), p));
}

// Corner k of a face, given the face's texel of triangles, in model space.
vec3 model_corner(const CylinderJob jb, uvec4 corners, uint k) {
    return imageLoad(positions, texel(jb.vertex_offset + corners[k])).xyz;
}

// The triangle a, a + e1, a + e2 against pixel (u, v) of an image `height` rows high.
bool line_hit(REAL3 a, REAL3 e1, REAL3 e2, uvec2 pixel, uint height, out REAL t) {
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

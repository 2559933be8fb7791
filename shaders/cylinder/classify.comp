#version 460
// Cylindrical Z-buffer, step 1 (seed 003, ch. 4): per (image, triangle), classify the triangle as
// seen from the axis (front: all V.N_xz >= 0, back: all <= 0, exception: mixed), split exception
// triangles along the plane through the axis where V.N_xz changes sign, and append one pixel
// rectangle per piece that conservatively covers its curved image in (theta, y) - two for a
// piece crossing the seam at theta = 0. Rectangles holding no pixel centre are dropped. The
// fragment stage then decides every pixel exactly.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/cylinder_layout.h"
#include "cylinder/cylinder_job.h"

layout(local_size_x = GIMG_CYL_CLASSIFY_GROUP) in;
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Triangles { uint triangles[]; };
layout(std430, binding = 2) readonly buffer Jobs { CylinderJob jobs[]; };
layout(std430, binding = 3) writeonly buffer Rects { uvec4 rects[]; };  // face, job, u0|u1<<16, v0|v1<<16
layout(std430, binding = 4) buffer Args { uint vertex_count; uint instance_count; uint first_vertex; uint first_instance; } args;
layout(push_constant) uniform Push { uint total_faces; uint job_count; uint width; uint height; uint max_rects; };

const float kTwoPi = 6.28318530717958647692;
const float kPi = 3.14159265358979323846;

uint job_of(uint i) {  // the last job whose face_prefix <= i
    uint lo = 0, hi = job_count - 1;
    while (lo < hi) {
        const uint mid = (lo + hi + 1) / 2;
        if (jobs[mid].face_prefix <= i) lo = mid; else hi = mid - 1;
    }
    return lo;
}

void append(uint face, uint job, float theta_lo, float theta_hi, float y_lo, float y_hi) {
    // Pixel centres inside [theta_lo, theta_hi] x [y_lo, y_hi], widened by a hair for rounding in
    // atan; an extra pixel costs one exact test, a missing one would be wrong.
    const float a = theta_lo / kTwoPi * float(width), b = theta_hi / kTwoPi * float(width);
    const float c = (1.0 - y_hi) * float(height), d = (1.0 - y_lo) * float(height);
    const int u0 = max(int(ceil(a - 0.5 - 1e-3)), 0), u1 = min(int(floor(b - 0.5 + 1e-3)), int(width) - 1);
    const int v0 = max(int(ceil(c - 0.5 - 1e-3)), 0), v1 = min(int(floor(d - 0.5 + 1e-3)), int(height) - 1);
    if (u0 > u1 || v0 > v1) return;
    const uint slot = atomicAdd(args.vertex_count, 3u) / 3u;  // one triangle per rectangle
    if (slot >= max_rects) return;  // cannot happen: at most GIMG_CYL_RECTS_PER_FACE per face
    rects[slot] = uvec4(face, job, uint(u0) | (uint(u1) << 16), uint(v0) | (uint(v1) << 16));
}

// A piece seen from its own side of the axis (front) or through the axis (back: x, z negated).
// Every point of a front piece has V.N_xz >= 0 (of a back piece, once negated, too), so its
// angles lie within a quarter turn of phi = angle(N_xz): measuring them from phi leaves no doubt
// which way round the piece's span goes, even when its split points are half a turn apart.
void emit_piece(uint face, uint job, vec3 p[4], uint count, bool back, vec2 n_xz) {
    const float phi = atan(n_xz.y, n_xz.x);
    float lo = 1e30, hi = -1e30, ylo = 1e30, yhi = -1e30;
    bool any_angle = false;
    for (uint k = 0; k < count; ++k) {
        ylo = min(ylo, p[k].y);
        yhi = max(yhi, p[k].y);
        const vec2 xz = back ? -p[k].xz : p[k].xz;
        if (dot(xz, xz) < 1e-24) continue;  // on the axis: no angle; the other points bound the span
        float delta = atan(xz.y, xz.x) - phi;
        delta -= kTwoPi * round(delta / kTwoPi);
        delta = clamp(delta, -0.5 * kPi, 0.5 * kPi);
        lo = min(lo, delta);
        hi = max(hi, delta);
        any_angle = true;
    }
    if (!any_angle) return;
    // Into [0, 2 pi) where possible; a span crossing theta = 0 is emitted on both sides of the seam.
    lo += phi;
    hi += phi;
    const float shift = kTwoPi * floor(lo / kTwoPi);
    lo -= shift;
    hi -= shift;
    append(face, job, lo, hi, ylo, yhi);
    if (hi > kTwoPi) append(face, job, lo - kTwoPi, hi - kTwoPi, ylo, yhi);
}

void main() {
    // 2D dispatch: more faces than one dimension's 65,535 workgroups can hold.
    const uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * GIMG_CYL_CLASSIFY_GROUP;
    if (i >= total_faces) return;
    const uint j = job_of(i);
    const CylinderJob job = jobs[j];
    const uint face = job.first_face + (i - job.face_prefix);
    vec3 v[3];
    for (uint k = 0; k < 3; ++k) {
        const uint idx = job.vertex_offset + triangles[3 * face + k];
        v[k] = to_cylinder(job, vec3(positions[3 * idx], positions[3 * idx + 1], positions[3 * idx + 2]));
    }
    const vec3 normal = cross(v[1] - v[0], v[2] - v[0]);
    const vec2 n_xz = normal.xz;
    if (dot(n_xz, n_xz) == 0.0) return;  // horizontal: no line perpendicular to the axis sees it
    const float s[3] = float[3](dot(v[0].xz, n_xz), dot(v[1].xz, n_xz), dot(v[2].xz, n_xz));
    const bool any_front = s[0] > 0.0 || s[1] > 0.0 || s[2] > 0.0;
    const bool any_back = s[0] < 0.0 || s[1] < 0.0 || s[2] < 0.0;
    vec3 piece[4];
    if (!(any_front && any_back)) {
        piece[0] = v[0], piece[1] = v[1], piece[2] = v[2];
        emit_piece(face, j, piece, 3u, any_back, n_xz);
        return;
    }
    // Exception triangle: split along s = 0 into a front piece (s >= 0) and a back piece (s <= 0).
    for (int side = 0; side < 2; ++side) {
        const float sign = side == 0 ? 1.0 : -1.0;
        uint n = 0;
        for (uint k = 0; k < 3; ++k) {
            const uint l = (k + 1) % 3;
            const float sk = sign * s[k], sl = sign * s[l];
            if (sk >= 0.0) piece[n++] = v[k];
            if ((sk > 0.0 && sl < 0.0) || (sk < 0.0 && sl > 0.0)) piece[n++] = mix(v[k], v[l], sk / (sk - sl));
        }
        emit_piece(face, j, piece, n, side == 1, n_xz);
    }
}

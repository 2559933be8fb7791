// Cylindrical Z-buffer, step 1 (seed 003, ch. 4): per (image, triangle), classify the triangle as
// seen from the axis (front: all V.N_xz >= 0, back: all <= 0, exception: mixed), split exception
// triangles along the plane through the axis where V.N_xz changes sign, and find one pixel
// rectangle per piece that conservatively covers its curved image in (theta, y) - two for a
// piece crossing the seam at theta = 0. Rectangles holding no pixel centre are dropped.
//
// A rectangle of at most small_pixels pixels is decided right here, pixel by pixel, with the
// fragment stage's own exact test (line_hit.glsl) and an atomicMax on ordered keys: a CPU
// rasteriser (lavapipe) spends about half a microsecond setting up each primitive, far more than
// testing a few pixels costs, and GPUs too rasterise pieces of a pixel or two poorly. Larger
// rectangles are appended for the graphics pipeline, whose fragment stage decides their pixels.
//
// Included by classify.comp (double) and classify_float.comp (float), REAL, REAL2, REAL3, REAL4 defined.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/cylinder_layout.h"
#include "cylinder/cylinder_job.h"
#include "cylinder/distance_key.glsl"

layout(local_size_x = GIMG_CYL_CLASSIFY_GROUP) in;
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Triangles { uint triangles[]; };
layout(std430, binding = 2) readonly buffer Jobs { CylinderJob jobs[]; };
layout(std430, binding = 3) writeonly buffer Rects { uvec4 rects[]; };  // face, job, u0|u1<<16, v0|v1<<16
layout(std430, binding = 4) buffer Args { uint vertex_count; uint instance_count; uint first_vertex; uint first_instance; } args;
layout(std430, binding = 5) readonly buffer Directions { REAL2 directions[]; };  // (cos, sin) of theta_u
layout(std430, binding = 6) buffer Small { uint small[]; };  // per atlas pixel: key of the largest t, 0: none
layout(push_constant) uniform Push {
    uint total_faces; uint job_count; uint width; uint height; uint max_rects; uint small_pixels; uint atlas_width;
};

#include "cylinder/line_hit.glsl"

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

// The pixel centres inside [theta_lo, theta_hi] x [y_lo, y_hi] as (u0, u1, v0, v1), widened by a
// hair for rounding in atan: an extra pixel costs one exact test, a missing one would be wrong.
ivec4 pixel_rect(float theta_lo, float theta_hi, float y_lo, float y_hi) {
    const float a = theta_lo / kTwoPi * float(width), b = theta_hi / kTwoPi * float(width);
    const float c = (1.0 - y_hi) * float(height), d = (1.0 - y_lo) * float(height);
    return ivec4(max(int(ceil(a - 0.5 - 1e-3)), 0), min(int(floor(b - 0.5 + 1e-3)), int(width) - 1),
                 max(int(ceil(c - 0.5 - 1e-3)), 0), min(int(floor(d - 0.5 + 1e-3)), int(height) - 1));
}

void main() {
    // 2D dispatch: more faces than one dimension's 65,535 workgroups can hold.
    const uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * GIMG_CYL_CLASSIFY_GROUP;
    if (i >= total_faces) return;
    const uint j = job_of(i);
    const CylinderJob job = jobs[j];
    const uint face = job.first_face + (i - job.face_prefix);
    vec3 model[3], v[3];
    for (uint k = 0; k < 3; ++k) {
        const uint idx = job.vertex_offset + triangles[3 * face + k];
        model[k] = vec3(positions[3 * idx], positions[3 * idx + 1], positions[3 * idx + 2]);
        v[k] = to_cylinder(job, model[k]);
    }
    const vec3 normal = cross(v[1] - v[0], v[2] - v[0]);
    const vec2 n_xz = normal.xz;
    const float s[3] = float[3](dot(v[0].xz, n_xz), dot(v[1].xz, n_xz), dot(v[2].xz, n_xz));
    const bool any_front = s[0] > 0.0 || s[1] > 0.0 || s[2] > 0.0;
    const bool any_back = s[0] < 0.0 || s[1] < 0.0 || s[2] < 0.0;
    const bool exception = any_front && any_back;
    // A horizontal triangle has no piece: no line perpendicular to the axis sees it.
    const int pieces = dot(n_xz, n_xz) == 0.0 ? 0 : (exception ? 2 : 1);
    // Angles are measured from phi = angle(N_xz): every point of a front piece has V.N_xz >= 0
    // (of a back piece, once x and z are negated, too), so they lie within a quarter turn of phi,
    // which leaves no doubt which way round the piece's span goes, even when its split points are
    // half a turn apart.
    const float phi = atan(n_xz.y, n_xz.x);

    // Up to four rectangles: two pieces (an exception triangle split along s = 0 into a front piece,
    // s >= 0, and a back piece, s <= 0; otherwise the whole triangle on its side), each emitted on
    // both sides of the seam at theta = 0 when its span crosses it.
    ivec4 rect[4];
    uint rect_count = 0;
    for (int side = 0; side < pieces; ++side) {
        const float sign = side == 0 ? 1.0 : -1.0;
        const bool back = exception ? side == 1 : any_back;
        vec3 piece[4];
        uint n = 0;
        for (uint k = 0; k < 3; ++k) {
            const uint l = (k + 1) % 3;
            const float sk = sign * s[k], sl = sign * s[l];
            if (!exception || sk >= 0.0) piece[n++] = v[k];
            if (exception && ((sk > 0.0 && sl < 0.0) || (sk < 0.0 && sl > 0.0))) piece[n++] = mix(v[k], v[l], sk / (sk - sl));
        }
        float lo = 1e30, hi = -1e30, ylo = 1e30, yhi = -1e30;
        bool any_angle = false;
        for (uint k = 0; k < n; ++k) {
            ylo = min(ylo, piece[k].y);
            yhi = max(yhi, piece[k].y);
            const vec2 xz = back ? -piece[k].xz : piece[k].xz;
            if (dot(xz, xz) < 1e-24) continue;  // on the axis: no angle; the other points bound the span
            float delta = atan(xz.y, xz.x) - phi;
            delta -= kTwoPi * round(delta / kTwoPi);
            delta = clamp(delta, -0.5 * kPi, 0.5 * kPi);
            lo = min(lo, delta);
            hi = max(hi, delta);
            any_angle = true;
        }
        // Into [0, 2 pi) where possible; a span crossing theta = 0 is emitted on both sides of the seam.
        lo += phi;
        hi += phi;
        const float shift = kTwoPi * floor(lo / kTwoPi);
        lo -= shift;
        hi -= shift;
        for (int copy = 0; copy < (any_angle ? (hi > kTwoPi ? 2 : 1) : 0); ++copy) {
            const ivec4 r = pixel_rect(lo - copy * kTwoPi, hi - copy * kTwoPi, ylo, yhi);
            if (r.x <= r.y && r.z <= r.w) rect[rect_count++] = r;
        }
    }

    // Small rectangles here, large ones to the graphics pipeline.
    REAL3 a = REAL3(0.0), e1 = REAL3(0.0), e2 = REAL3(0.0);
    bool fetched = false;
    for (uint k = 0; k < rect_count; ++k) {
        const ivec4 r = rect[k];
        if (uint(r.y - r.x + 1) * uint(r.w - r.z + 1) > small_pixels) {
            const uint slot = atomicAdd(args.vertex_count, 3u) / 3u;  // one triangle per rectangle
            if (slot < max_rects)  // always: at most GIMG_CYL_RECTS_PER_FACE per face
                rects[slot] = uvec4(face, j, uint(r.x) | (uint(r.y) << 16), uint(r.z) | (uint(r.w) << 16));
            continue;
        }
        if (!fetched) {  // the corners in REAL precision, from the positions already loaded
            a = cylinder_point(job, model[0]);
            e1 = cylinder_point(job, model[1]) - a;
            e2 = cylinder_point(job, model[2]) - a;
            fetched = true;
        }
        for (int y = r.z; y <= r.w; ++y)
            for (int x = r.x; x <= r.y; ++x) {
                REAL t;
                if (line_hit(a, e1, e2, uvec2(x, y), height, t))
                    atomicMax(small[(job.tile_y + uint(y)) * atlas_width + job.tile_x + uint(x)], distance_key(float(t)));
            }
    }
}

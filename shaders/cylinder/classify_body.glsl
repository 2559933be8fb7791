// Cylindrical Z-buffer, step 1 (the cylindrical-projection thesis, ch. 4): per (image, triangle), classify the triangle as
// seen from the axis (front: all V.N_xz >= 0, back: all <= 0, exception: mixed), split exception
// triangles along the plane through the axis where V.N_xz changes sign, and find one pixel
// rectangle per piece that conservatively covers its curved image in (theta, y) - two for a
// piece crossing the seam at theta = 0. Rectangles holding no pixel centre are dropped.
//
// A rectangle of at most small_pixels pixels is decided right here, pixel by pixel, with the
// fragment stage's own exact test (line_hit.glsl) and an atomicMax on ordered keys: a CPU
// rasteriser (lavapipe) spends about half a microsecond setting up each primitive, far more than
// testing a few pixels costs, and GPUs too rasterise pieces of a pixel or two poorly. Larger
// rectangles are appended for the large-piece pass: the graphics pipeline, whose fragment stage
// decides their pixels, or large_pieces.comp, a workgroup sharing out each one's pixels.
//
// Written for how lavapipe runs compute (Mesa 22.3, 8 lanes a vector): both sides of every branch
// execute under a lane mask, a loop runs until its slowest lane is done, and a storage-buffer load
// or atomic with per-lane addresses is a loop over the lanes. Hence one atan per corner (not per
// corner and piece), no atan for split points, rectangles held in named variables rather than an
// array indexed by a per-lane count, one flat loop over all of a face's small pixels, and the
// geometry in images (common/texel_array.glsl). Measured on armadillo at 540x270: 8.2 -> 5.8 ms.
//
// Included by classify.comp (double) and classify_float.comp (float), REAL, REAL2, REAL3, REAL4 defined.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/piece_passes.glsl"

layout(local_size_x = GIMG_CYL_CLASSIFY_GROUP) in;

const float kTwoPi = 6.28318530717958647692;
const float kPi = 3.14159265358979323846;

uint job_of(uint i) {  // the last job whose face_prefix <= i
    // Between the jobs of its block's first face and of the next block's: mostly one job, so the
    // search takes no step, where one over all jobs took log2(jobs) gathers.
    const uint b = i / GIMG_CYL_JOB_BLOCK;
    uint lo = job_of_block(b, job_count);
    uint hi = (b + 1) * GIMG_CYL_JOB_BLOCK < total_faces ? job_of_block(b + 1, job_count) : job_count - 1;
    while (lo < hi) {
        const uint mid = (lo + hi + 1) / 2;
        if (job_face_prefix(mid) <= i) lo = mid; else hi = mid - 1;
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
    const CylinderJob job = load_job(j);
    const uint face = job.first_face + (i - job.face_prefix);
    const uvec4 corners = imageLoad(triangles, texel(face));
    vec3 model[3], v[3];
    for (uint k = 0; k < 3; ++k) {
        model[k] = model_corner(job, corners, k);
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
    // Each corner's angle from phi, in [-pi, pi], for the front (xz) and the back (-xz): one atan
    // per corner, not one per corner and piece. Corners on the axis have no angle.
    float front_delta[3], back_delta[3];
    bool off_axis[3];
    for (uint k = 0; k < 3; ++k) {
        const vec2 xz = v[k].xz;
        off_axis[k] = dot(xz, xz) >= 1e-24;
        float d = atan(xz.y, xz.x) - phi;
        d -= kTwoPi * round(d / kTwoPi);
        front_delta[k] = clamp(d, -0.5 * kPi, 0.5 * kPi);
        const float b = d - (d > 0.0 ? kPi : -kPi);  // the angle of -xz
        back_delta[k] = clamp(b, -0.5 * kPi, 0.5 * kPi);
    }
    const vec2 perp = vec2(-n_xz.y, n_xz.x);  // phi + a quarter turn

    // Up to four rectangles: two pieces (an exception triangle split along s = 0 into a front piece,
    // s >= 0, and a back piece, s <= 0; otherwise the whole triangle on its side), each emitted on
    // both sides of the seam at theta = 0 when its span crosses it. They are kept in order in
    // small0..small3 and large0..large3 (selects, not arrays indexed by a per-lane count: lavapipe
    // turns those into memory traffic lane by lane).
    ivec4 small0 = ivec4(0, -1, 0, -1), small1 = small0, small2 = small0, small3 = small0;
    ivec4 large0 = small0, large1 = small0, large2 = small0, large3 = small0;
    uint small_count = 0, large_count = 0;
    for (int side = 0; side < pieces; ++side) {
        const float sign = side == 0 ? 1.0 : -1.0;
        const bool back = exception ? side == 1 : any_back;
        float lo = 1e30, hi = -1e30, ylo = 1e30, yhi = -1e30;
        bool any_angle = false;
        for (uint k = 0; k < 3; ++k) {
            const uint l = (k + 1) % 3;
            const float sk = sign * s[k], sl = sign * s[l];
            if (!exception || sk >= 0.0) {  // corner k belongs to this piece
                ylo = min(ylo, v[k].y);
                yhi = max(yhi, v[k].y);
                if (off_axis[k]) {
                    const float d = back ? back_delta[k] : front_delta[k];
                    lo = min(lo, d);
                    hi = max(hi, d);
                    any_angle = true;
                }
            }
            if (exception && ((sk > 0.0 && sl < 0.0) || (sk < 0.0 && sl > 0.0))) {
                // Edge k crosses s = 0 at a point whose xz is perpendicular to N_xz: a quarter turn
                // either side of phi, exactly, so no atan is needed.
                const vec3 q = mix(v[k], v[l], sk / (sk - sl));
                ylo = min(ylo, q.y);
                yhi = max(yhi, q.y);
                const vec2 xz = back ? -q.xz : q.xz;
                if (dot(xz, xz) >= 1e-24) {
                    const float d = dot(xz, perp) >= 0.0 ? 0.5 * kPi : -0.5 * kPi;
                    lo = min(lo, d);
                    hi = max(hi, d);
                    any_angle = true;
                }
            }
        }
        // Into [0, 2 pi) where possible; a span crossing theta = 0 is emitted on both sides of the seam.
        lo += phi;
        hi += phi;
        const float shift = kTwoPi * floor(lo / kTwoPi);
        lo -= shift;
        hi -= shift;
        const int copies = any_angle ? (hi > kTwoPi ? 2 : 1) : 0;
        for (int copy = 0; copy < copies; ++copy) {
            const ivec4 r = pixel_rect(lo - copy * kTwoPi, hi - copy * kTwoPi, ylo, yhi);
            if (r.x > r.y || r.z > r.w) continue;
            if (uint(r.y - r.x + 1) * uint(r.w - r.z + 1) > small_pixels) {
                large0 = large_count == 0 ? r : large0;
                large1 = large_count == 1 ? r : large1;
                large2 = large_count == 2 ? r : large2;
                large3 = large_count == 3 ? r : large3;
                ++large_count;
                continue;
            }
            small0 = small_count == 0 ? r : small0;
            small1 = small_count == 1 ? r : small1;
            small2 = small_count == 2 ? r : small2;
            small3 = small_count == 3 ? r : small3;
            ++small_count;
        }
    }

    // Large rectangles go to the large-piece pass (graphics pipeline or compute) through a loop that
    // no lane enters unless it has one: lavapipe skips a loop all lanes leave at once, where an if
    // would run its atomics' loop over the lanes in every subgroup.
    for (uint k = 0; k < large_count; ++k) {
        const uint slot = atomicAdd(args.rect_count, 1u);
        atomicAdd(args.vertex_count, 3u);  // one triangle a rectangle
        if (slot < GIMG_CYL_MAX_GROUPS) atomicAdd(args.groups_x, 1u);
        if (slot < max_rects)  // always: at most GIMG_CYL_RECTS_PER_FACE per face
            rects[slot] = uvec4(face, j, uint(large0.x) | (uint(large0.y) << 16),
                                uint(large0.z) | (uint(large0.w) << 16));
        large0 = large1;
        large1 = large2;
        large2 = large3;
    }

    const REAL3 a = cylinder_point(job, model[0]);
    const REAL3 b = cylinder_point(job, model[1]);
    const REAL3 c = cylinder_point(job, model[2]);
    const uint origin = job.tile_y * atlas_width + job.tile_x;
    const uint pixels = uint(small0.y - small0.x + 1) * uint(small0.w - small0.z + 1) +
                        uint(small1.y - small1.x + 1) * uint(small1.w - small1.z + 1) +
                        uint(small2.y - small2.x + 1) * uint(small2.w - small2.z + 1) +
                        uint(small3.y - small3.x + 1) * uint(small3.w - small3.z + 1);
    ivec2 p = small0.xz;
    for (uint step = 0; step < pixels; ++step) {
        REAL t;
        if (line_hit(a, b, c, uvec2(p), height, t))
            atomicMax(small[origin + uint(p.y) * atlas_width + uint(p.x)], distance_key(float(t)));
        const bool row_done = p.x == small0.y;
        const bool rect_done = row_done && p.y == small0.w;
        p = rect_done ? small1.xz : (row_done ? ivec2(small0.x, p.y + 1) : ivec2(p.x + 1, p.y));
        small0 = rect_done ? small1 : small0;
        small1 = rect_done ? small2 : small1;
        small2 = rect_done ? small3 : small2;
    }
}

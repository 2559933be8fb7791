// Cylindrical Z-buffer, step 2 in compute: the pieces the classify pass found too large to decide
// in one lane (more than small_pixels pixels), a workgroup a piece, its lanes sharing out the
// piece's pixel rectangle. Each pixel gets the exact test of line_hit.glsl and an atomicMax on the
// small-piece keys, as in the classify pass, so the image is the graphics pipeline's.
//
// The alternative to the graphics pipeline's curved raster for devices that rasterise on the CPU:
// lavapipe sets up every primitive on one thread. Bunny at 540x270 (222 large pieces) took
// 5.0-5.2 ms an image with them drawn, 4.5-4.7 ms with this pass, 4.1-4.2 ms with them skipped.
//
// Included by large_pieces.comp (double) and large_pieces_float.comp (float), REAL, REAL2, REAL3,
// REAL4 and REAL2_OF_TEXEL defined.
#extension GL_GOOGLE_include_directive : require
#define PIECES_READ_ONLY
#include "cylinder/piece_passes.glsl"

layout(local_size_x = GIMG_CYL_LARGE_GROUP) in;

void main() {
    // One dispatch holds at most GIMG_CYL_MAX_GROUPS workgroups; each takes every that-many-th piece.
    for (uint r = gl_WorkGroupID.x; r < min(args.rect_count, max_rects); r += gl_NumWorkGroups.x) {
        const uvec4 rect = rects[r];
        const CylinderJob job = load_job(rect.y);
        const uvec4 corners = imageLoad(triangles, texel(rect.x));
        const REAL3 a = cylinder_point(job, model_corner(job, corners, 0));
        const REAL3 b = cylinder_point(job, model_corner(job, corners, 1));
        const REAL3 c = cylinder_point(job, model_corner(job, corners, 2));
        const uint u0 = rect.z & 0xffffu, v0 = rect.w & 0xffffu;
        const uint columns = (rect.z >> 16) - u0 + 1, pixels = columns * ((rect.w >> 16) - v0 + 1);
        const uint origin = job.tile_y * atlas_width + job.tile_x;
        for (uint k = gl_LocalInvocationIndex; k < pixels; k += GIMG_CYL_LARGE_GROUP) {
            const uvec2 p = uvec2(u0 + k % columns, v0 + k / columns);
            REAL t;
            if (line_hit(a, b, c, p, height, t))
                atomicMax(small[origin + p.y * atlas_width + p.x], distance_key(float(t)));
        }
    }
}

// The bindings the classify pass and the large-piece compute pass share (one binding list in
// passes/cylinder/zbuffer.cpp), and the helpers both use. The classify pass writes the rectangles
// and counts them; the large-piece pass defines PIECES_READ_ONLY first and reads them.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/cylinder_layout.h"
#include "cylinder/cylinder_job.h"
#include "cylinder/distance_key.glsl"
#include "common/texel_array.glsl"

#ifdef PIECES_READ_ONLY
#define PIECES_ACCESS readonly
#define RECTS_ACCESS readonly
#else
#define PIECES_ACCESS
#define RECTS_ACCESS writeonly
#endif

layout(binding = 0, rgba32f) uniform readonly image2D positions;    // texel v: (x, y, z, 0)
layout(binding = 1, rgba32ui) uniform readonly uimage2D triangles;  // texel f: (a, b, c, 0)
layout(binding = 2, rgba32ui) uniform readonly uimage2D job_texels;  // job k: texels 5k .. 5k + 4 (CylinderJob)
layout(std430, binding = 3) RECTS_ACCESS buffer Rects { uvec4 rects[]; };  // face, job, u0|u1<<16, v0|v1<<16
// What the classify pass counts for the large pieces, mirrored by PieceArgs in zbuffer.cpp: the
// graphics pipeline's indirect draw (three vertices a rectangle), the large-piece compute pass's
// indirect dispatch (a workgroup a rectangle, at most GIMG_CYL_MAX_GROUPS; the pass loops over any
// more) and the number of rectangles.
layout(std430, binding = 4) PIECES_ACCESS buffer Args {
    uint vertex_count; uint instance_count; uint first_vertex; uint first_instance;
    uint groups_x; uint groups_y; uint groups_z;
    uint rect_count;
} args;
layout(binding = 5, rgba32ui) uniform readonly uimage2D directions;  // texel u: cos, sin of theta_u (line_hit.glsl)
layout(std430, binding = 6) buffer Small { uint small[]; };  // per atlas pixel: key of the largest t, 0: none
layout(push_constant) uniform Push {
    uint total_faces; uint job_count; uint width; uint height; uint max_rects; uint small_pixels; uint atlas_width;
};

#include "cylinder/job_texels.glsl"
#include "cylinder/line_hit.glsl"

// A batch's images out of the atlas (add_cylinder): per pixel the largest t found, from the compute
// passes' ordered keys and, with RASTER_T, the graphics pipeline's t; NaN where nothing was hit,
// the form reconstruction reads. The same decision as the host merge in zbuffer.cpp.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/cylinder_layout.h"
#include "cylinder/distance_key.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Keys { uint keys[]; };  // per atlas pixel, 0: no hit
layout(std430, binding = 1) writeonly buffer Images { float images[]; };  // image after image, row-major
#ifdef RASTER_T
layout(binding = 2, r32f) uniform readonly image2D raster_t;  // GIMG_CYL_EMPTY: no hit
#endif
layout(push_constant) uniform Push { uint width, height, count, tiles_per_row, atlas_width; };

void main() {
    const uvec3 p = gl_GlobalInvocationID;
    if (p.x >= width || p.y >= height || p.z >= count) return;
    const uvec2 a = uvec2((p.z % tiles_per_row) * width + p.x, (p.z / tiles_per_row) * height + p.y);
    const uint key = keys[a.y * atlas_width + a.x];
    float d = key != 0u ? key_distance(key) : float(GIMG_CYL_EMPTY);
#ifdef RASTER_T
    d = max(d, imageLoad(raster_t, ivec2(a)).x);
#endif
    images[(p.z * height + p.y) * width + p.x] = d >= -1.0 ? d : uintBitsToFloat(0x7fc00000u);
}

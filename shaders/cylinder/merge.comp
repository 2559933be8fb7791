#version 460
// Cylindrical Z-buffer, step 4: the largest t per pixel of the two rasterisers - the graphics
// pipeline's (large pieces, in the atlas through the depth test) and the classify pass's (small
// pieces, as ordered keys) - into the atlas.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/distance_key.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0, r32f) uniform image2D atlas;
layout(std430, binding = 1) readonly buffer Small { uint small[]; };
layout(push_constant) uniform Push { uint atlas_width; uint atlas_height; };

void main() {
    const uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= atlas_width || p.y >= atlas_height) return;
    const uint key = small[p.y * atlas_width + p.x];
    if (key == 0u) return;
    const float t = key_distance(key);
    if (t > imageLoad(atlas, ivec2(p)).r) imageStore(atlas, ivec2(p), vec4(t));
}

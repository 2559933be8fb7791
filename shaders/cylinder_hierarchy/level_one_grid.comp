#version 460
// Level one's grid: point (u, v) from the level-1 band, t = 1 - d along the inward radial ray
// (level_step.glsl).
#extension GL_GOOGLE_include_directive : require
#include "cylinder_hierarchy/level_step.glsl"

void main() {
    const uint u = gl_GlobalInvocationID.x, v = gl_GlobalInvocationID.y;
    if (u >= side || v >= side) return;
    const uint i = v * side + u;
    const uvec2 sample_ = imageLoad(bands, ivec2(u, v)).xy;
    const uvec4 t[2] = level_one_point(u, v, uintBitsToFloat(sample_.x), sample_.y);
    imageStore(grid_texels, texel(2u * i), t[0]);
    imageStore(grid_texels, texel(2u * i + 1u), t[1]);
}

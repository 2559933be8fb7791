#version 460
// The next grid (side 2S) from the grid, its cells and the level's stored samples: the old point,
// then the H, V and D launches' points (level_step.glsl).
#extension GL_GOOGLE_include_directive : require
#include "cylinder_hierarchy/level_step.glsl"

void store_point(uint i, uvec4 t[2]) {
    imageStore(next_texels, texel(2u * i), t[0]);
    imageStore(next_texels, texel(2u * i + 1u), t[1]);
}

// The new point (u, v) of the 2S grid from its launch and stored sample.
void put(uint u, uint v, GridLaunch l, ivec2 at_band) {
    const uvec2 sample_ = imageLoad(bands, at_band).xy;
    store_point(v * (2u * side) + u, sample_point(u, v, l, uintBitsToFloat(sample_.x), sample_.y));
}

void main() {
    const uint u = gl_GlobalInvocationID.x, v = gl_GlobalInvocationID.y;
    if (u >= side || v >= side) return;
    const uint i = v * side + u, o = (2u * v) * (2u * side) + 2u * u;
    imageStore(next_texels, texel(2u * o), imageLoad(grid_texels, texel(2u * i)));
    imageStore(next_texels, texel(2u * o + 1u), imageLoad(grid_texels, texel(2u * i + 1u)));
    put(2u * u + 1u, 2u * v, h_launch(u, v), band_h(u, v));
    put(2u * u, 2u * v + 1u, v_launch(u, v), band_v(u, v));
    put(2u * u + 1u, 2u * v + 1u, d_launch(u, v, false), band_d(u, v));
}

#version 460
#extension GL_GOOGLE_include_directive : require
// A hierarchy level's grid on the GPU (the decoder's, and the encoder's between its levels): the
// CPU's launch_rays.cpp term for term in double precision (precise: no fused multiply-add). One
// shader, three steps chosen by `step`:
//  0 level one: grid point (u, v) from the level-1 band, t = 1 - d along the inward radial ray;
//  1 cells: the D launch of every cell (its corners' mean, the oriented mean of the fan's unit
//    normals);
//  2 edges and interleave: the H and V launches, then the next grid (side 2S): G'[2v][2u] = G,
//    [2v][2u + 1] = H, [2v + 1][2u] = V, [2v + 1][2u + 1] = D, each new point origin + t normal.
// Kinds: 0 empty, 1 hit, 2 a miss kept on the surface, 3 a radial ray's hit (as
// CylinderHierarchy::valid). Rows wrap: those below the bottom sit above row 0 (launch_rays.h).
layout(local_size_x = 8, local_size_y = 8) in;

// The N x N image: (t as a float, kind) per sample, in the band layout.
layout(binding = 0, rg32ui) uniform readonly uimage2D bands;
// cos, sin per level-1 column, then per next grid of side M = 2B, 4B, .. N per column (from M - B)
layout(std430, binding = 1) readonly buffer Directions { double dirs[]; };
layout(binding = 2, rgba32ui) uniform uimage2D grid_texels;  // level_grid.glsl's layouts
layout(binding = 3, rgba32ui) uniform uimage2D cell_texels;
layout(binding = 4, rgba32ui) uniform writeonly uimage2D next_texels;  // the 2S grid's
layout(push_constant) uniform Push {
    uint step;
    uint side;  // S
    uint n;     // the image's side N
    uint base;  // B
};

#include "cylinder_hierarchy/level_grid.glsl"

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
    const uint i = v * side + u;
    if (step == 0u) {
        const uvec2 sample_ = imageLoad(bands, ivec2(u, v)).xy;
        const uvec4 t[2] = level_one_point(u, v, uintBitsToFloat(sample_.x), sample_.y);
        imageStore(grid_texels, texel(2u * i), t[0]);
        imageStore(grid_texels, texel(2u * i + 1u), t[1]);
        return;
    }
    if (step == 1u) {
        imageStore(cell_texels, texel(4u * i + 1u), uvec4(0u));  // not valid
        if (!rows_adjacent(v)) return;
        const GridPoint a = grid_point(at(u, v)), b = grid_point(at(u + 1u, v));
        const GridPoint c = grid_point(at(u, v + 1u)), d = grid_point(at(u + 1u, v + 1u));
        if (a.kind == 0u || b.kind == 0u || c.kind == 0u || d.kind == 0u) return;
        precise dvec3 sum4 = ((a.p + b.p) + c.p) + d.p;
        precise dvec3 origin = 0.25LF * sum4;
        const double out_d = a.outward + b.outward + c.outward + d.outward >= 0.0LF ? 1.0LF : -1.0LF;
        dvec3 sum = dvec3(0.0LF);
        const dvec3 ring[4] = dvec3[4](c.p, a.p, b.p, d.p);
        for (int k = 0; k < 4; ++k) add_unit_normal(sum, origin, ring[k], ring[(k + 1) % 4]);
        const dvec3 normal = oriented(sum, origin, out_d);
        imageStore(cell_texels, texel(4u * i), uvec4(unpackDouble2x32(origin.x), unpackDouble2x32(origin.y)));
        imageStore(cell_texels, texel(4u * i + 1u),
                   uvec4(unpackDouble2x32(origin.z), floatBitsToUint(float(out_d)), 1u));
        imageStore(cell_texels, texel(4u * i + 2u), uvec4(unpackDouble2x32(normal.x), unpackDouble2x32(normal.y)));
        imageStore(cell_texels, texel(4u * i + 3u), uvec4(unpackDouble2x32(normal.z), 0u, 0u));
        return;
    }
    // Step 2: the old point, then H, V and D into the next grid.
    const uint o = (2u * v) * (2u * side) + 2u * u;
    imageStore(next_texels, texel(2u * o), imageLoad(grid_texels, texel(2u * i)));
    imageStore(next_texels, texel(2u * o + 1u), imageLoad(grid_texels, texel(2u * i + 1u)));
    put(2u * u + 1u, 2u * v, h_launch(u, v), band_h(u, v));
    put(2u * u, 2u * v + 1u, v_launch(u, v), band_v(u, v));
    put(2u * u + 1u, 2u * v + 1u, d_launch(u, v, false), band_d(u, v));
}

// A hierarchy level's grid on the GPU (the decoder's, and the encoder's between its levels): the
// CPU's launch_rays.cpp term for term in double precision (precise: no fused multiply-add), in
// three steps, one shader each, which share these bindings:
//  level_one_grid.comp: grid point (u, v) from the level-1 band, t = 1 - d along the inward radial ray;
//  grid_cells.comp: the D launch of every cell (its corners' mean, the oriented mean of the fan's
//    unit normals);
//  next_grid.comp: the H and V launches, then the next grid (side 2S): G'[2v][2u] = G,
//    [2v][2u + 1] = H, [2v + 1][2u] = V, [2v + 1][2u + 1] = D, each new point origin + t normal.
// Three shaders, not one with a step constant: lavapipe runs both sides of every branch under a
// lane mask, so one shader cost each step the arithmetic of all three.
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
    uint side;  // S
    uint n;     // the image's side N
    uint base;  // B
};

#include "cylinder_hierarchy/level_grid.glsl"

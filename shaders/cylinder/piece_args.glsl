// What the classify pass counts for the large pieces, mirrored by PieceArgs in
// passes/cylinder/zbuffer.cpp: the graphics pipeline's indirect draw (three vertices a rectangle),
// the large-piece compute pass's indirect dispatch (a workgroup a rectangle, at most
// GIMG_CYL_MAX_GROUPS; the pass loops over any more) and the number of rectangles. Readers define
// PIECE_ARGS_ACCESS readonly first.
#ifndef PIECE_ARGS_ACCESS
#define PIECE_ARGS_ACCESS
#endif
layout(std430, binding = 4) PIECE_ARGS_ACCESS buffer Args {
    uint vertex_count; uint instance_count; uint first_vertex; uint first_instance;
    uint groups_x; uint groups_y; uint groups_z;
    uint rect_count;
} args;

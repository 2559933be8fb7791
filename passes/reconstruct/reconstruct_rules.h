#pragma once
// The rules of grid reconstruction, shared by the CPU reference and the GPU path so both make the
// same decisions (and mirrored, operation for operation, by shaders/reconstruct/*.comp):
//  - cylindrical pixel -> point: p_cyl = (d cos theta_u, y_v, d sin theta_u) in double, then
//    p = R^T (p_cyl - t) / s, then float;
//  - a block is its four pixels a = (u, v), b = (u + 1, v), c = (u, v + 1), d = (u + 1, v + 1)
//    (u + 1 wrapping for cylindrical images); it makes two triangles when all four are valid and
//    its jump (cylindrical: max d - min d; positions: largest squared distance, against T^2) is
//    within the threshold;
//  - the diagonal is a-d when |a - d|^2 <= |b - c|^2 (exact in double from float points), else b-c;
//  - winding: cylindrical blocks face the wall they are seen from (d > 0: away from the axis,
//    d < 0: towards it; the sign of the sum of the four d), position images face +s x +t of their
//    parameters (row 0 at t = 1).
// Everything else (normals, caps) happens on the CPU after the grid, for both paths.

#include "gimg/passes/reconstruct.h"

namespace gimg::passes::detail {

// The three corners of the block's two triangles, as pixel offsets in {a, b, c, d} = {0, 1, 2, 3}.
struct BlockTriangles {
    std::uint8_t corner[2][3];
};
BlockTriangles block_triangles(bool diagonal_ad, bool faces_plus);

// The reconstructed mesh's normals (angle-weighted), and caps for cylindrical images.
void add_caps(geo::Mesh& mesh, const CylinderImage& image, const CylinderFrame& frame);
void finish_mesh(geo::Mesh& mesh);

// Blocks whose four pixels are all valid (the most a grid can make triangles from).
std::size_t full_blocks(const std::vector<std::uint8_t>& covered, std::uint32_t width, std::uint32_t height, bool wrap);

// Validates sizes and the LOD divisibility; throws geo::InputError.
void check_reconstructible(std::uint32_t width, std::uint32_t height, std::uint32_t lod);

}  // namespace gimg::passes::detail

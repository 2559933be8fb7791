#version 460
// The D launch of every cell of the grid: its corners' mean and the oriented mean of the fan's unit
// normals (level_step.glsl).
#extension GL_GOOGLE_include_directive : require
#include "cylinder_hierarchy/level_step.glsl"

void main() {
    const uint u = gl_GlobalInvocationID.x, v = gl_GlobalInvocationID.y;
    if (u >= side || v >= side) return;
    const uint i = v * side + u;
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
    imageStore(cell_texels, texel(4u * i + 1u), uvec4(unpackDouble2x32(origin.z), floatBitsToUint(float(out_d)), 1u));
    imageStore(cell_texels, texel(4u * i + 2u), uvec4(unpackDouble2x32(normal.x), unpackDouble2x32(normal.y)));
    imageStore(cell_texels, texel(4u * i + 3u), uvec4(unpackDouble2x32(normal.z), 0u, 0u));
}

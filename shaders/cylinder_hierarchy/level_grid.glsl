// A hierarchy level's grid and launches, passes/cylinder_hierarchy/launch_rays.cpp term for term
// in double precision, shared by the decoder (level_step.glsl) and the encoder (cast_level.glsl).
// Declare before including: the texel arrays grid_texels (RGBA32UI, 2 texels a point: x, y | z,
// outward as a float, kind) and cell_texels (4 a cell: origin x, y | origin z, outward, valid |
// normal x, y | normal z), the buffer dirs (level_step.glsl says how it is laid out), and side
// (S), n (the image's side N) and base (B). Texel arrays, not buffers: lavapipe gathers from images
// but loads from storage buffers lane by lane (common/texel_array.glsl).
#include "common/double_cpu.glsl"
#include "common/texel_array.glsl"

struct GridPoint {
    dvec3 p;
    double outward;
    uint kind;  // 0 empty
};

GridPoint grid_point(uint i) {
    const uvec4 a = imageLoad(grid_texels, texel(2u * i)), b = imageLoad(grid_texels, texel(2u * i + 1u));
    return GridPoint(dvec3(packDouble2x32(a.xy), packDouble2x32(a.zw), packDouble2x32(b.xy)),
                     double(uintBitsToFloat(b.z)), b.w);
}

uvec4[2] grid_texel_pair(dvec3 p, double outward, uint kind) {
    return uvec4[2](uvec4(unpackDouble2x32(p.x), unpackDouble2x32(p.y)),
                    uvec4(unpackDouble2x32(p.z), floatBitsToUint(float(outward)), kind));
}

struct CellOrigin {
    dvec3 origin;
    double outward;
    bool valid;
};

CellOrigin cell_origin(uint c) {
    const uvec4 a = imageLoad(cell_texels, texel(4u * c)), b = imageLoad(cell_texels, texel(4u * c + 1u));
    return CellOrigin(dvec3(packDouble2x32(a.xy), packDouble2x32(a.zw), packDouble2x32(b.xy)),
                      double(uintBitsToFloat(b.z)), b.w != 0u);
}

dvec3 cell_normal(uint c) {
    const uvec4 a = imageLoad(cell_texels, texel(4u * c + 2u)), b = imageLoad(cell_texels, texel(4u * c + 3u));
    return dvec3(packDouble2x32(a.xy), packDouble2x32(a.zw), packDouble2x32(b.xy));
}

uint at(uint u, uint v) { return (v % side) * side + (u % side); }

// launch_rays.cpp's row_height and rows_adjacent.
double row_height(uint j, uint grid_side) {
    const double b = double(base);
    precise double y = 1.0LF - (double(j) * (b / double(grid_side)) + 0.5LF) / b;
    if (y > 0.0LF) return y;
    precise double wrapped = y + 1.0LF;
    return wrapped;
}
bool rows_adjacent(uint v) { return row_height(v, side) > row_height((v + 1u) % side, side); }

void add_unit_normal(inout dvec3 sum, dvec3 a, dvec3 b, dvec3 c) {
    precise dvec3 ba = b - a;
    precise dvec3 ca = c - a;
    const dvec3 nn = cross_cpu(ba, ca);
    const double len = length_cpu(nn);
    if (len > 0.0LF && !isinf(len) && !isnan(len)) {
        precise dvec3 s = sum + nn / len;
        sum = s;
    }
}

// sqrt(x^2 + z^2), as launch_rays.cpp's radius.
double radius(dvec3 p) {
    precise double r = sqrt(p.x * p.x + p.z * p.z);
    return r;
}

dvec3 oriented(dvec3 sum, dvec3 origin, double outward) {
    const double len = length_cpu(sum);
    if (len > 1e-12LF) {
        precise dvec3 r = (outward * sum) / len;
        return r;
    }
    const double r = radius(origin);
    const dvec3 radial = r > 0.0LF ? dvec3(origin.x / r, 0.0LF, origin.z / r) : dvec3(1.0LF, 0.0LF, 0.0LF);
    return outward * radial;
}

// The distance between two points (glm::distance).
double span_between(dvec3 a, dvec3 b) {
    precise dvec3 d = b - a;
    return length_cpu(d);
}

// Where the bands of the level of side S lie in the N x N image (x, y): H right of the S x S
// block, V below, D bottom-right.
ivec2 band_h(uint u, uint v) { return ivec2(side + u, v); }
ivec2 band_v(uint u, uint v) { return ivec2(u, side + v); }
ivec2 band_d(uint u, uint v) { return ivec2(side + u, side + v); }

struct GridLaunch {
    bool valid;
    dvec3 origin;
    dvec3 normal;
    double outward;
    double span;
};

GridLaunch no_launch(dvec3 origin, double outward) {
    return GridLaunch(false, origin, dvec3(0.0LF), outward, 0.0LF);
}

// H: between (u, v) and (u + 1, v); the cells below (row v) and above (row v - 1).
GridLaunch h_launch(uint u, uint v) {
    const GridPoint a = grid_point(at(u, v)), b = grid_point(at(u + 1u, v));
    precise dvec3 origin = 0.5LF * (a.p + b.p);
    if (a.kind == 0u || b.kind == 0u) return no_launch(origin, a.outward);
    dvec3 sum = dvec3(0.0LF);
    const CellOrigin below = cell_origin(at(u, v)), above = cell_origin(at(u, v + side - 1u));
    if (below.valid) add_unit_normal(sum, a.p, b.p, below.origin);
    if (above.valid) add_unit_normal(sum, b.p, a.p, above.origin);
    return GridLaunch(true, origin, oriented(sum, origin, a.outward), a.outward, span_between(a.p, b.p));
}

// V: between (u, v) and (u, v + 1); the cells to the right (column u) and left (column u - 1).
GridLaunch v_launch(uint u, uint v) {
    const GridPoint a = grid_point(at(u, v));
    const bool has_lower = rows_adjacent(v);
    const GridPoint c = has_lower ? grid_point(at(u, v + 1u)) : a;
    precise dvec3 origin = 0.5LF * (a.p + c.p);
    if (!has_lower || a.kind == 0u || c.kind == 0u) return no_launch(origin, a.outward);
    dvec3 sum = dvec3(0.0LF);
    const CellOrigin right = cell_origin(at(u, v)), left = cell_origin(at(u + side - 1u, v));
    if (right.valid) add_unit_normal(sum, c.p, a.p, right.origin);
    if (left.valid) add_unit_normal(sum, a.p, c.p, left.origin);
    return GridLaunch(true, origin, oriented(sum, origin, a.outward), a.outward, span_between(a.p, c.p));
}

// D: the cell's launch (grid_cells.comp computed it); with `spans`, its span the longer
// diagonal.
GridLaunch d_launch(uint u, uint v, bool spans) {
    const CellOrigin c = cell_origin(at(u, v));
    if (!c.valid) return no_launch(c.origin, c.outward);
    double span = 0.0LF;
    if (spans) {
        const dvec3 a = grid_point(at(u, v)).p, b = grid_point(at(u + 1u, v)).p;
        const dvec3 cc = grid_point(at(u, v + 1u)).p, d = grid_point(at(u + 1u, v + 1u)).p;
        span = max(span_between(a, d), span_between(b, cc));
    }
    return GridLaunch(true, c.origin, cell_normal(at(u, v)), c.outward, span);
}

// Band 0 H, 1 V or 2 D of grid point (u, v).
GridLaunch grid_launch(uint band, uint u, uint v, bool spans) {
    return band == 0u ? h_launch(u, v) : band == 1u ? v_launch(u, v) : d_launch(u, v, spans);
}

// The radial launch of the next grid's sample (col, row): valid where the row's height lies
// strictly within the cylinder's; origin on the wall, normal the inward direction.
GridLaunch radial_launch(uint col, uint row) {
    GridLaunch l;
    const double y = row_height(row, 2u * side);
    const uint k = 2u * side - base + col;
    l.valid = y > 0.0LF && y < 1.0LF;
    l.origin = dvec3(dirs[2 * k], y, dirs[2 * k + 1]);
    l.normal = dvec3(-dirs[2 * k], 0.0LF, -dirs[2 * k + 1]);
    l.outward = 1.0LF;
    l.span = 0.0LF;
    return l;
}

// Grid points from stored samples (t as stored, kind), as the CPU decoder places them. Level 1's
// pixel (u, v): d = 1 - t along the inward radial direction at the row's height.
uvec4[2] level_one_point(uint u, uint v, float t, uint kind) {
    if (kind == 0u) return grid_texel_pair(dvec3(0.0LF), 1.0LF, 0u);
    precise double d = 1.0LF - double(t);
    precise double x = d * dirs[2 * u];
    precise double z = d * dirs[2 * u + 1];
    return grid_texel_pair(dvec3(x, row_height(v, side), z), d >= 0.0LF ? 1.0LF : -1.0LF, kind);
}

// The 2S grid's point (col, row) from its launch `l`: origin + t normal; a radial sample from the
// radial launch at its own column and row.
uvec4[2] sample_point(uint col, uint row, GridLaunch l, float t, uint kind) {
    if (kind == 3u) {
        l = radial_launch(col, row);
        l.outward = t <= 1.0 ? 1.0LF : -1.0LF;
    }
    if (!l.valid || kind == 0u) return grid_texel_pair(dvec3(0.0LF), 1.0LF, 0u);
    precise dvec3 p = l.origin + double(t) * l.normal;
    return grid_texel_pair(p, l.outward, kind);
}

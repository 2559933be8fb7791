#version 460
// Decoding a hierarchy on the GPU: the CPU's launch_rays.cpp term for term in double precision
// (precise: no fused multiply-add). One shader, three steps chosen by `step`:
//  0 level one: grid point (u, v) from the level-1 band, t = 1 - d along the inward radial ray;
//  1 cells: the D launch of every cell (its corners' mean, the oriented mean of the fan's unit
//    normals);
//  2 edges and interleave: the H and V launches, then the next grid (side 2S): G'[2v][2u] = G,
//    [2v][2u + 1] = H, [2v + 1][2u] = V, [2v + 1][2u + 1] = D, each new point origin + t normal.
// Validity: 0 empty, 1 hit, 2 a miss kept on the surface, 3 a radial ray's hit (as
// CylinderHierarchy::valid). Rows wrap: those below the bottom sit above row 0 (launch_rays.h).
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer BandT { float band_t[]; };      // N x N
layout(std430, binding = 1) readonly buffer BandValid { uint band_valid[]; };
// cos, sin per level-1 column, then per next grid of side M = 2B, 4B, .. N per column (from M - B)
layout(std430, binding = 2) readonly buffer Directions { double dirs[]; };
layout(std430, binding = 3) buffer Grid { double grid[]; };                // 4 per point: x, y, z, outward
layout(std430, binding = 4) buffer GridValid { uint grid_valid[]; };
layout(std430, binding = 5) buffer Cells { double cell[]; };               // 8 per cell: origin, normal, outward, valid
layout(std430, binding = 6) buffer Next { double next[]; };                // 4 per point of the 2S grid
layout(std430, binding = 7) buffer NextValid { uint next_valid[]; };
layout(push_constant) uniform Push {
    uint step;
    uint side;  // S
    uint n;     // the image's side N
    uint base;  // B
};

dvec3 cross_cpu(dvec3 x, dvec3 y) {
    precise dvec3 r = dvec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y);
    return r;
}
double dot_cpu(dvec3 x, dvec3 y) {
    precise double r = (x.x * y.x + x.y * y.y) + x.z * y.z;
    return r;
}
double length_cpu(dvec3 x) { return sqrt(dot_cpu(x, x)); }

dvec3 point(uint i) { return dvec3(grid[4 * i], grid[4 * i + 1], grid[4 * i + 2]); }
double outward_of(uint i) { return grid[4 * i + 3]; }
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
dvec3 cell_origin(uint c) { return dvec3(cell[8 * c], cell[8 * c + 1], cell[8 * c + 2]); }
bool cell_valid(uint c) { return cell[8 * c + 7] != 0.0LF; }

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

dvec3 oriented(dvec3 sum, dvec3 origin, double outward) {
    const double len = length_cpu(sum);
    if (len > 1e-12LF) {
        precise dvec3 r = (outward * sum) / len;
        return r;
    }
    precise double r = sqrt(origin.x * origin.x + origin.z * origin.z);
    const dvec3 radial = r > 0.0LF ? dvec3(origin.x / r, 0.0LF, origin.z / r) : dvec3(1.0LF, 0.0LF, 0.0LF);
    return outward * radial;
}

// The bands of the level of side S: H right of the S x S block, V below, D bottom-right.
uint band_h(uint u, uint v) { return v * n + side + u; }
uint band_v(uint u, uint v) { return (side + v) * n + u; }
uint band_d(uint u, uint v) { return (side + v) * n + side + u; }

void put(uint u, uint v, bool launch_valid, dvec3 origin, dvec3 normal, double outward, uint band) {
    const uint i = v * (2u * side) + u;
    const uint kind = band_valid[band];
    if (kind == 3u) {  // a radial ray at this sample's angle and height
        const double y = row_height(v, 2u * side);
        const uint k = 2u * side - base + u;
        launch_valid = y > 0.0LF && y < 1.0LF;
        origin = dvec3(dirs[2 * k], y, dirs[2 * k + 1]);
        normal = dvec3(-dirs[2 * k], 0.0LF, -dirs[2 * k + 1]);
        outward = band_t[band] <= 1.0 ? 1.0LF : -1.0LF;
    }
    if (!launch_valid || kind == 0u) {
        next[4 * i] = 0.0LF;
        next[4 * i + 1] = 0.0LF;
        next[4 * i + 2] = 0.0LF;
        next[4 * i + 3] = 1.0LF;
        next_valid[i] = 0u;
        return;
    }
    precise dvec3 p = origin + double(band_t[band]) * normal;
    next[4 * i] = p.x;
    next[4 * i + 1] = p.y;
    next[4 * i + 2] = p.z;
    next[4 * i + 3] = outward;
    next_valid[i] = kind;
}

void main() {
    const uint u = gl_GlobalInvocationID.x, v = gl_GlobalInvocationID.y;
    if (u >= side || v >= side) return;
    const uint i = v * side + u;
    if (step == 0u) {
        const uint b = v * n + u;
        precise double d = 1.0LF - double(band_t[b]);
        const double y = row_height(v, side);
        if (band_valid[b] != 0u) {
            precise double x = d * dirs[2 * u];
            precise double z = d * dirs[2 * u + 1];
            grid[4 * i] = x;
            grid[4 * i + 1] = y;
            grid[4 * i + 2] = z;
            grid[4 * i + 3] = d >= 0.0LF ? 1.0LF : -1.0LF;
        } else {
            grid[4 * i] = 0.0LF;
            grid[4 * i + 1] = 0.0LF;
            grid[4 * i + 2] = 0.0LF;
            grid[4 * i + 3] = 1.0LF;
        }
        grid_valid[i] = band_valid[b];
        return;
    }
    if (step == 1u) {
        cell[8 * i + 7] = 0.0LF;
        if (!rows_adjacent(v)) return;
        const uint a = at(u, v), b = at(u + 1u, v), c = at(u, v + 1u), d = at(u + 1u, v + 1u);
        if (grid_valid[a] == 0u || grid_valid[b] == 0u || grid_valid[c] == 0u || grid_valid[d] == 0u) return;
        precise dvec3 sum4 = ((point(a) + point(b)) + point(c)) + point(d);
        precise dvec3 origin = 0.25LF * sum4;
        const double out_d =
            outward_of(a) + outward_of(b) + outward_of(c) + outward_of(d) >= 0.0LF ? 1.0LF : -1.0LF;
        dvec3 sum = dvec3(0.0LF);
        const dvec3 ring[4] = dvec3[4](point(c), point(a), point(b), point(d));
        for (int k = 0; k < 4; ++k) add_unit_normal(sum, origin, ring[k], ring[(k + 1) % 4]);
        const dvec3 normal = oriented(sum, origin, out_d);
        cell[8 * i] = origin.x;
        cell[8 * i + 1] = origin.y;
        cell[8 * i + 2] = origin.z;
        cell[8 * i + 3] = normal.x;
        cell[8 * i + 4] = normal.y;
        cell[8 * i + 5] = normal.z;
        cell[8 * i + 6] = out_d;
        cell[8 * i + 7] = 1.0LF;
        return;
    }
    // Step 2: the old point, then H, V and D into the next grid.
    const uint a = at(u, v), b = at(u + 1u, v);
    const uint o = (2u * v) * (2u * side) + 2u * u;
    for (uint k = 0u; k < 4u; ++k) next[4 * o + k] = grid[4 * i + k];
    next_valid[o] = grid_valid[i];
    {  // H: between (u, v) and (u + 1, v); the cells below (row v) and above (row v - 1).
        const bool valid = grid_valid[a] != 0u && grid_valid[b] != 0u;
        precise dvec3 origin = 0.5LF * (point(a) + point(b));
        dvec3 sum = dvec3(0.0LF);
        if (valid && cell_valid(at(u, v))) add_unit_normal(sum, point(a), point(b), cell_origin(at(u, v)));
        if (valid && cell_valid(at(u, v + side - 1u)))
            add_unit_normal(sum, point(b), point(a), cell_origin(at(u, v + side - 1u)));
        const dvec3 normal = valid ? oriented(sum, origin, outward_of(a)) : dvec3(0.0LF);
        put(2u * u + 1u, 2u * v, valid, origin, normal, outward_of(a), band_h(u, v));
    }
    {  // V: between (u, v) and (u, v + 1); the cells to the right (column u) and left (column u - 1).
        const bool has_lower = rows_adjacent(v);
        const uint c = has_lower ? at(u, v + 1u) : a;
        const bool valid = has_lower && grid_valid[a] != 0u && grid_valid[c] != 0u;
        precise dvec3 origin = 0.5LF * (point(a) + point(c));
        dvec3 sum = dvec3(0.0LF);
        if (valid) {
            const uint right = at(u, v), left = at(u + side - 1u, v);
            if (cell_valid(right)) add_unit_normal(sum, point(c), point(a), cell_origin(right));
            if (cell_valid(left)) add_unit_normal(sum, point(a), point(c), cell_origin(left));
        }
        const dvec3 normal = valid ? oriented(sum, origin, outward_of(a)) : dvec3(0.0LF);
        put(2u * u, 2u * v + 1u, valid, origin, normal, outward_of(a), band_v(u, v));
    }
    {  // D: the cell's launch.
        const uint ci = at(u, v);
        const bool valid = cell_valid(ci);
        const dvec3 origin = cell_origin(ci);
        const dvec3 normal = dvec3(cell[8 * ci + 3], cell[8 * ci + 4], cell[8 * ci + 5]);
        put(2u * u + 1u, 2u * v + 1u, valid, origin, normal, cell[8 * ci + 6], band_d(u, v));
    }
}

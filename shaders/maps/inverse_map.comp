#version 460
// MAPS's Pi^{-1} at one point of the base domain per thread (sec. 2.4): the point is looked up in
// its base triangle's chart, then in its corners' z^a charts (largest barycentric coordinate
// first), cell by cell of each chart's grid; the first original triangle whose image holds it
// gives its position. Same order of operations as evaluate_inverse_map (passes/maps).
//
// The map's arrays are texel arrays (common/texel_array.glsl; upload_inverse_map says how each is
// packed): lavapipe gathers from images, and loads from storage buffers lane by lane.
#extension GL_GOOGLE_include_directive : require
#include "common/texel_array.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D face_charts;     // 2 per base face: 8 uints
layout(binding = 1, rgba32ui) uniform readonly uimage2D corner_coords;   // 9 dvec2 per base face
layout(binding = 2, rgba32ui) uniform readonly uimage2D chart_box;       // 2 per chart: origin, cell size
layout(binding = 3, rgba32ui) uniform readonly uimage2D chart_grid;      // per chart: nx, ny, first cell, 0
layout(binding = 4, r32ui) uniform readonly uimage2D cell_offsets;
layout(binding = 5, r32ui) uniform readonly uimage2D cell_items;
layout(binding = 6, rgba32ui) uniform readonly uimage2D triangle_coords; // 3 dvec2 per chart triangle
layout(binding = 7, r32ui) uniform readonly uimage2D triangle_face;
layout(binding = 8, rgba32ui) uniform readonly uimage2D positions;       // 2 per original vertex: xy, z0
layout(binding = 9, rgba32ui) uniform readonly uimage2D faces;           // per original face: a, b, c, 0
layout(std430, binding = 10) readonly buffer Points { uint point_face[]; };
layout(std430, binding = 11) readonly buffer Bary { double point_bary[]; };  // 3 per point
layout(std430, binding = 12) writeonly buffer Out { double result[]; };      // x, y, z, flag per point
layout(push_constant) uniform Push { uint first, count; };  // this dispatch's points: first .. first + count

uint best_triangle;
dvec3 best_bary;
double best_margin;

// Images of different formats cannot share a function parameter: macros.
#define DVEC2_AT(image, i) dvec2_of(imageLoad(image, texel(i)))
#define UINT_AT(image, i) imageLoad(image, texel(i)).x
dvec2 dvec2_of(uvec4 t) { return dvec2(packDouble2x32(t.xy), packDouble2x32(t.zw)); }
uint face_chart(uint f, uint k) { return imageLoad(face_charts, texel(2u * f + (k >> 2u)))[k & 3u]; }
dvec3 position(uint v) { return dvec3(DVEC2_AT(positions, 2u * v), DVEC2_AT(positions, 2u * v + 1u).x); }

double cross2(dvec2 a, dvec2 b) {
    precise double r = a.x * b.y - a.y * b.x;
    return r;
}

dvec3 barycentric_2d(dvec2 p, dvec2 a, dvec2 b, dvec2 c) {
    precise double d = cross2(b - a, c - a);
    if (d == 0.0LF) return dvec3(-1.0LF);  // a degenerate triangle holds no point
    precise double u = cross2(b - p, c - p) / d;
    precise double v = cross2(c - p, a - p) / d;
    precise double w = 1.0LF - u - v;
    return dvec3(u, v, w);
}

void test_items(uint begin, uint end, dvec2 p) {
    for (uint i = begin; i < end; ++i) {
        const uint t = UINT_AT(cell_items, i);
        const dvec3 w = barycentric_2d(p, DVEC2_AT(triangle_coords, 3u * t), DVEC2_AT(triangle_coords, 3u * t + 1u),
                                       DVEC2_AT(triangle_coords, 3u * t + 2u));
        const double margin = min(min(w.x, w.y), w.z);
        if (margin > best_margin) {
            best_triangle = t;
            best_bary = w;
            best_margin = margin;
        }
        if (margin >= -1e-12LF) return;
    }
}

// The cell of the chart's grid holding p, or with `whole` every cell of the chart.
void search_chart(uint chart, dvec2 p, bool whole) {
    const dvec2 origin = DVEC2_AT(chart_box, 2u * chart), size = DVEC2_AT(chart_box, 2u * chart + 1u);
    const uvec3 grid = imageLoad(chart_grid, texel(chart)).xyz;
    if (whole) {
        test_items(UINT_AT(cell_offsets, grid.z), UINT_AT(cell_offsets, grid.z + grid.x * grid.y), p);
        return;
    }
    precise double fx = floor((p.x - origin.x) / size.x);
    precise double fy = floor((p.y - origin.y) / size.y);
    if (!(fx >= 0.0LF && fy >= 0.0LF && fx < double(grid.x) && fy < double(grid.y))) return;
    const uint cell = grid.z + uint(fy) * grid.x + uint(fx);
    test_items(UINT_AT(cell_offsets, cell), UINT_AT(cell_offsets, cell + 1u), p);
}

void main() {
    if (gl_GlobalInvocationID.x >= count) return;
    const uint i = first + gl_GlobalInvocationID.x;
    const uint f = point_face[i];
    const dvec3 b = dvec3(point_bary[3u * i], point_bary[3u * i + 1u], point_bary[3u * i + 2u]);
    best_triangle = 0xffffffffu;
    best_bary = dvec3(0.0LF);
    best_margin = -1e300LF;
    // Corners by decreasing barycentric coordinate, ties the lower corner first.
    uint order[3];
    for (uint c = 0u; c < 3u; ++c) {
        uint rank = 0u;
        for (uint d = 0u; d < 3u; ++d)
            if (b[d] > b[c] || (b[d] == b[c] && d < c)) ++rank;
        order[rank] = c;
    }
    // The cells holding the point, then, for a point in a gap between charts, whole charts.
    for (uint pass = 0u; pass < 2u; ++pass) {
        if (best_margin >= -1e-9LF) break;
        const bool whole = pass == 1u;
        search_chart(face_chart(f, 0u), dvec2(b.y, b.z), whole);
        for (uint r = 0u; r < 3u; ++r) {
            if (best_margin >= -1e-12LF) break;
            const uint c = order[r];
            const uint base = 9u * f + 3u * c;
            precise dvec2 x = b.x * DVEC2_AT(corner_coords, base) + b.y * DVEC2_AT(corner_coords, base + 1u);
            precise dvec2 y = x + b.z * DVEC2_AT(corner_coords, base + 2u);
            search_chart(face_chart(f, 1u + c), y, whole);
        }
    }
    // A base vertex is an original vertex: exactly its position.
    if (b.x == 1.0LF || b.y == 1.0LF || b.z == 1.0LF) {
        const dvec3 p = position(face_chart(f, 4u + (b.x == 1.0LF ? 0u : b.y == 1.0LF ? 1u : 2u)));
        for (uint k = 0u; k < 3u; ++k) result[4u * i + k] = p[k];
        result[4u * i + 3u] = 0.0LF;
        return;
    }
    if (best_triangle == 0xffffffffu) {
        result[4u * i + 3u] = -1.0LF;
        return;
    }
    precise dvec3 w = max(best_bary, dvec3(0.0LF));
    precise double sum = w.x + w.y + w.z;
    w = sum > 0.0LF ? w / sum : dvec3(1.0LF / 3.0LF);
    const uvec3 corners = imageLoad(faces, texel(UINT_AT(triangle_face, best_triangle))).xyz;
    const dvec3 pa = position(corners.x), pb = position(corners.y), pc = position(corners.z);
    for (uint k = 0u; k < 3u; ++k) {
        precise double p = w.x * pa[k] + w.y * pb[k];
        precise double q = p + w.z * pc[k];
        result[4u * i + k] = q;
    }
    result[4u * i + 3u] = best_margin < -1e-9LF ? 1.0LF : 0.0LF;
}

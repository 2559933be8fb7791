#version 460
// MAPS's Pi^{-1} at one point of the base domain per thread (sec. 2.4): the point is looked up in
// its base triangle's chart, then in its corners' z^a charts (largest barycentric coordinate
// first), cell by cell of each chart's grid; the first original triangle whose image holds it
// gives its position. Same order of operations as evaluate_inverse_map (passes/maps).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer FaceCharts { uint face_charts[]; };      // 8 per base face
layout(std430, binding = 1) readonly buffer CornerCoords { double corner_coords[]; }; // 18 per base face
layout(std430, binding = 2) readonly buffer ChartBox { double chart_box[]; };         // 4 per chart
layout(std430, binding = 3) readonly buffer ChartGrid { uint chart_grid[]; };         // 4 per chart
layout(std430, binding = 4) readonly buffer CellOffsets { uint cell_offsets[]; };
layout(std430, binding = 5) readonly buffer CellItems { uint cell_items[]; };
layout(std430, binding = 6) readonly buffer TriangleCoords { double triangle_coords[]; };  // 6 per triangle
layout(std430, binding = 7) readonly buffer TriangleFace { uint triangle_face[]; };
layout(std430, binding = 8) readonly buffer Positions { double positions[]; };  // 3 per original vertex
layout(std430, binding = 9) readonly buffer Faces { uint faces[]; };            // 3 per original face
layout(std430, binding = 10) readonly buffer Points { uint point_face[]; };
layout(std430, binding = 11) readonly buffer Bary { double point_bary[]; };     // 3 per point
layout(std430, binding = 12) writeonly buffer Out { double result[]; };         // x, y, z, flag per point
layout(push_constant) uniform Push { uint first, count; };  // this dispatch's points: first .. first + count

uint best_triangle;
dvec3 best_bary;
double best_margin;

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

dvec2 tri_coord(uint t, uint k) { return dvec2(triangle_coords[6u * t + 2u * k], triangle_coords[6u * t + 2u * k + 1u]); }

void test_items(uint begin, uint end, dvec2 p) {
    for (uint i = begin; i < end; ++i) {
        const uint t = cell_items[i];
        const dvec3 w = barycentric_2d(p, tri_coord(t, 0u), tri_coord(t, 1u), tri_coord(t, 2u));
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
    const dvec4 box = dvec4(chart_box[4u * chart], chart_box[4u * chart + 1u], chart_box[4u * chart + 2u],
                            chart_box[4u * chart + 3u]);
    const uvec3 grid = uvec3(chart_grid[4u * chart], chart_grid[4u * chart + 1u], chart_grid[4u * chart + 2u]);
    if (whole) {
        test_items(cell_offsets[grid.z], cell_offsets[grid.z + grid.x * grid.y], p);
        return;
    }
    precise double fx = floor((p.x - box.x) / box.z);
    precise double fy = floor((p.y - box.y) / box.w);
    if (!(fx >= 0.0LF && fy >= 0.0LF && fx < double(grid.x) && fy < double(grid.y))) return;
    const uint cell = grid.z + uint(fy) * grid.x + uint(fx);
    test_items(cell_offsets[cell], cell_offsets[cell + 1u], p);
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
        search_chart(face_charts[8u * f], dvec2(b.y, b.z), whole);
        for (uint r = 0u; r < 3u; ++r) {
            if (best_margin >= -1e-12LF) break;
            const uint c = order[r];
            const uint base = 18u * f + 6u * c;
            precise dvec2 x = b.x * dvec2(corner_coords[base], corner_coords[base + 1u]) +
                              b.y * dvec2(corner_coords[base + 2u], corner_coords[base + 3u]);
            precise dvec2 y = x + b.z * dvec2(corner_coords[base + 4u], corner_coords[base + 5u]);
            search_chart(face_charts[8u * f + 1u + c], y, whole);
        }
    }
    // A base vertex is an original vertex: exactly its position.
    if (b.x == 1.0LF || b.y == 1.0LF || b.z == 1.0LF) {
        const uint v = face_charts[8u * f + 4u + (b.x == 1.0LF ? 0u : b.y == 1.0LF ? 1u : 2u)];
        for (uint k = 0u; k < 3u; ++k) result[4u * i + k] = positions[3u * v + k];
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
    const uint o = triangle_face[best_triangle];
    const uint a = faces[3u * o], bb = faces[3u * o + 1u], c = faces[3u * o + 2u];
    for (uint k = 0u; k < 3u; ++k) {
        precise double p = w.x * positions[3u * a + k] + w.y * positions[3u * bb + k];
        precise double q = p + w.z * positions[3u * c + k];
        result[4u * i + k] = q;
    }
    result[4u * i + 3u] = best_margin < -1e-9LF ? 1.0LF : 0.0LF;
}

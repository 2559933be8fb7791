#version 460
// P'_o = P_o + F(u_i, v_i) for every region vertex i of original vertex o (Kuriyama & Kaneko
// sec. 5), in the CPU twin's order of operations: mode 0 a lattice of offsets on clamped cubic
// B-splines (the fixed layers already zero), mode 1 the built-in bump, mode 2 a height map, the
// heights along the vertex normals.
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Positions { double positions[]; };  // 3 per vertex, deformed in place
layout(std430, binding = 1) readonly buffer Normals { double normals[]; };  // 3 per vertex (paste)
layout(std430, binding = 2) readonly buffer Original { uint original[]; };  // per region vertex
layout(std430, binding = 3) readonly buffer Params { double uv[]; };        // 2 per region vertex
layout(std430, binding = 4) readonly buffer Offsets { double offsets[]; };  // 3 per control point (mode 0)
layout(std430, binding = 5) readonly buffer Heights { float heights[]; };   // width x height (mode 2)
layout(push_constant) uniform Push {
    uint count, mode, columns, rows;  // rows x columns lattice, or the height map's height x width
    double scale;                     // paste: the height times the bounding-box diagonal
};

const uint kMaxKnots = 132u;  // lattices of up to 128 control points a side
double basis[kMaxKnots];

double knot(uint i, uint n) {
    const uint spans = n - 3u;
    if (i < 3u) return 0.0LF;
    if (i <= 3u + spans) return double(i - 3u) / double(spans);
    return 1.0LF;
}

// The n clamped cubic B-spline values at x (Cox-de Boor), into basis[0..n).
void cubic_basis(uint n, double x) {
    const uint knots = n + 4u;
    x = clamp(x, 0.0LF, 1.0LF);
    for (uint i = 0u; i + 1u < knots; ++i) {
        const double a = knot(i, n), b = knot(i + 1u, n);
        basis[i] = a < b && ((x >= a && x < b) || (x == 1.0LF && b == 1.0LF)) ? 1.0LF : 0.0LF;
    }
    for (uint p = 1u; p <= 3u; ++p)
        for (uint i = 0u; i + p + 1u < knots; ++i) {
            const double ki = knot(i, n), kp = knot(i + p, n), k1 = knot(i + 1u, n), kp1 = knot(i + p + 1u, n);
            precise double l = kp > ki ? (x - ki) / (kp - ki) * basis[i] : 0.0LF;
            precise double r = kp1 > k1 ? (kp1 - x) / (kp1 - k1) * basis[i + 1u] : 0.0LF;
            basis[i] = l + r;
        }
}

double bump(double x) {
    x = clamp(x, 0.0LF, 1.0LF);
    precise double t = 4.0LF * x * (1.0LF - x);
    precise double cube = t * t * t;
    return cube;
}

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    const uint o = original[i];
    if (o == 0xffffffffu) return;
    const dvec2 p = dvec2(uv[2u * i], uv[2u * i + 1u]);
    precise dvec3 f = dvec3(0.0LF);
    if (mode == 0u) {
        double bu[128];
        cubic_basis(columns, p.x);
        for (uint k = 0u; k < columns; ++k) bu[k] = basis[k];
        cubic_basis(rows, p.y);
        for (uint q = 0u; q < rows; ++q)
            for (uint k = 0u; k < columns; ++k) {
                const uint c = 3u * (q * columns + k);
                precise double w = bu[k] * basis[q];
                f += dvec3(offsets[c], offsets[c + 1u], offsets[c + 2u]) * w;
            }
    } else {
        double g;
        if (mode == 1u) {
            precise double b = bump(p.x) * bump(p.y);
            g = b;
        } else {
            const double x = clamp(p.x, 0.0LF, 1.0LF) * double(columns - 1u);
            const double y = (1.0LF - clamp(p.y, 0.0LF, 1.0LF)) * double(rows - 1u);
            const uint x0 = min(uint(x), columns - 2u), y0 = min(uint(y), rows - 2u);
            const double fx = x - double(x0), fy = y - double(y0);
            const double h00 = double(heights[y0 * columns + x0]), h10 = double(heights[y0 * columns + x0 + 1u]);
            const double h01 = double(heights[(y0 + 1u) * columns + x0]), h11 = double(heights[(y0 + 1u) * columns + x0 + 1u]);
            precise double top = h00 * (1.0LF - fx) + h10 * fx;
            precise double bottom = h01 * (1.0LF - fx) + h11 * fx;
            precise double mixed = top * (1.0LF - fy) + bottom * fy;
            g = mixed;
        }
        const dvec3 n = dvec3(normals[3u * o], normals[3u * o + 1u], normals[3u * o + 2u]);
        precise double h = g * scale;
        f = n * h;
    }
    for (uint k = 0u; k < 3u; ++k) {
        precise double moved = positions[3u * o + k] + f[k];
        positions[3u * o + k] = moved;
    }
}

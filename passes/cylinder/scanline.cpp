// The paper's own CPU algorithm for cylindrical geometry images: the cylindrical Z-buffer of
// the cylindrical-projection thesis, chapter 4. Triangles are projected onto the cylinder one at a time and scan-converted
// row by row; a depth test keeps the largest signed distance d per pixel. It gives the image of
// the ray-casting definition in cylinder.h, to rounding, at the cost of a 2D line intersection
// per covered pixel instead of a 3D ray-triangle test per candidate.
//
//   (z1) each triangle is a front, back (seen through the axis: x and z negated, d negated) or
//        exception triangle by the signs of V_i . N_xz; an exception triangle is cut where the
//        sign changes, which on a triangle is always a horizontal line: between two scan rows.
//   (z2) its edges are labelled left (theta_min) and right (theta_max); per row the scan plane's
//        cut points on those edges are found in 3D, projected to theta, and a row that crosses
//        theta = 0 is mended by adding 2 pi to theta_max (eq. 4.2).
//   (z3) each pixel ray z = gamma_u x of the row meets the row's cut z = alpha x + beta at
//        x_u = beta / (gamma_u - alpha), d_u = |x_u| sqrt(1 + gamma_u^2) (eqs. 4.5, 4.6), from
//        tables over the columns; the largest d_u per pixel wins (z3-a).
#include "gimg/passes/cylinder.h"
#include "gimg/geometry/error.h"

#include "gimg/engine/error.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numbers>
#include <string>
#include <thread>
#include <utility>

namespace gimg::passes {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr float kEmpty = -4.0f;  // below every d in [-1, 1]
// Below this many faces per thread, starting threads costs more than it saves.
constexpr std::size_t kFacesPerThread = 16384;

struct Point {
    double x, y, z;
};

// The tabulated ray of one column (eqs. 4.4, 4.6). The paper's z = gamma x with gamma = tan theta
// blows up where cos theta ~ 0, so columns nearer the z axis than the x axis use the same
// equations with x and z swapped (x = gamma z, gamma = cot theta). Both are folded into one
// denominator a dx + b dz: (gamma, -1) for the first kind of column, (-1, gamma) for the second.
struct ColumnRay {
    double a, b, secant;  // secant = sqrt(1 + gamma^2)
};

struct Raster {
    std::uint32_t width = 0, height = 0;
    double columns_per_radian = 0.0;
    std::vector<ColumnRay> rays;
    std::vector<std::array<double, 2>> directions;  // (cos, sin) of theta_u, cylinder_directions()
    std::vector<double> row_y;                      // y_v, computed once so every decision sees the same values
    float* depth = nullptr;                         // the Z-buffer, W x H, row-major from the top
};

Raster make_raster(std::uint32_t width, std::uint32_t height, float* depth) {
    Raster r;
    r.width = width;
    r.height = height;
    r.columns_per_radian = double(width) / kTwoPi;
    r.depth = depth;
    r.directions = cylinder_directions(width);
    for (const auto& [c, s] : r.directions) {
        if (std::abs(c) >= std::abs(s)) {
            const double gamma = s / c;
            r.rays.push_back({gamma, -1.0, std::sqrt(1.0 + gamma * gamma)});
        } else {
            const double gamma = c / s;
            r.rays.push_back({-1.0, gamma, std::sqrt(1.0 + gamma * gamma)});
        }
    }
    r.row_y.resize(height);
    for (std::uint32_t v = 0; v < height; ++v) r.row_y[v] = 1.0 - (double(v) + 0.5) / double(height);
    return r;
}

// theta = atan(z / x) of a point seen from the axis, in [0, 2 pi] (eq. 2.1), to within 1e-5
// (Abramowitz and Stegun 4.4.49): less than a fifth of a column even at 65535 columns, and
// column_at() settles the column exactly. (libm's atan2 took a third of the whole run.)
double theta_of(double x, double z) {
    const double ax = std::abs(x), az = std::abs(z);
    const double t = std::min(ax, az) / std::max(ax, az), t2 = t * t;
    double a = t * (0.9998660 + t2 * (-0.3302995 + t2 * (0.1801410 + t2 * (-0.0851330 + t2 * 0.0208351))));
    if (az > ax) a = 0.5 * kPi - a;
    if (x < 0.0) a = kPi - a;
    return z < 0.0 ? kTwoPi - a : a;
}

// The first column whose ray lies at or after the point (x, z), counter-clockwise, given the
// point's theta. A row covers [column_at(left), column_at(right)): half-open, so of two triangles
// sharing an edge exactly one takes a pixel centre on it, both deciding on the same cut point.
// The decision is the sign of the 2D cross product of the point with the column's tabulated
// direction, the same directions the ray-casting definition uses; theta only says where to look.
// Columns run on past W - 1 to W (column 0 after a full turn).
long column_at(const Raster& r, double x, double z, double theta) {
    const long w = long(r.width);
    if (w < 8) {  // columns so far apart that a neighbour may lie half a turn away: compare thetas
        const double exact = std::atan2(z, x);
        return long(std::ceil((exact < 0.0 ? exact + kTwoPi : exact) * r.columns_per_radian - 0.5));
    }
    const auto at_or_after = [&](long u) {
        const auto& [c, s] = r.directions[std::size_t(u < w ? u : u - w)];
        return x * s - z * c >= 0.0;
    };
    long u = std::clamp(long(theta * r.columns_per_radian + 0.5), 0L, w);  // ceil(theta W / 2 pi - 1/2), +-1
    while (u > 0 && at_or_after(u - 1)) --u;
    while (u < w && !at_or_after(u)) ++u;
    return u;
}

// An edge walked from its lower end (lo.y <= hi.y), with the paper's 3D step per unit of height,
// dp = (hi - lo) / (hi.y - lo.y) (z2.b). The paper adds dp from row to row; taking
// lo + (y - lo.y) dp instead reaches the same point without accumulating rounding, and because
// a shared edge is walked from the same end in both of its triangles, they cut it at bit for bit
// the same point: no crack between them.
struct Edge {
    Point lo, hi;
    double dx_dy, dz_dy;
};

Edge make_edge(const Point& lo, const Point& hi) {
    const double dy = hi.y - lo.y;  // 0 for a horizontal edge, whose ends are all a row needs
    const double per_y = dy > 0.0 ? 1.0 / dy : 0.0;
    return {lo, hi, (hi.x - lo.x) * per_y, (hi.z - lo.z) * per_y};
}

// The edge's cut by the scan plane at height y (lo.y <= y <= hi.y): its end points exactly when
// the plane passes through them.
Point cut(const Edge& e, double y) {
    if (y == e.lo.y) return e.lo;
    if (y == e.hi.y) return e.hi;
    const double t = y - e.lo.y;
    return {e.lo.x + t * e.dx_dy, y, e.lo.z + t * e.dz_dy};
}

// Rows v with y_lo <= y_v <= y_hi, within [row_begin, row_end); empty when first > last.
std::pair<long, long> rows_between(const Raster& r, double y_lo, double y_hi, long row_begin, long row_end) {
    // v = H (1 - y) - 1/2 from y_v = 1 - (v + 1/2) / H: an estimate, settled on the row heights
    // themselves below, so that every caller agrees on which rows a height range holds.
    const double h = double(r.height);
    const double top = h * (1.0 - y_hi) - 0.5, bottom = h * (1.0 - y_lo) - 0.5;
    if (!(top < double(row_end)) || !(bottom > double(row_begin) - 1.0)) return {1, 0};
    long first = top > double(row_begin) ? long(top) : row_begin;               // at most one row early
    long last = bottom < double(row_end - 1) ? long(bottom) + 1 : row_end - 1;  // at most two rows late
    while (first < row_end && r.row_y[std::size_t(first)] > y_hi) ++first;
    while (first > row_begin && r.row_y[std::size_t(first) - 1] <= y_hi) --first;
    while (last >= row_begin && r.row_y[std::size_t(last)] < y_lo) --last;
    while (last + 1 < row_end && r.row_y[std::size_t(last) + 1] >= y_lo) ++last;
    return {first, last};
}

// (z2.b2, z2.b3, z3) One row of one piece: its cut runs from `left` to `right` (x, z already
// negated for a back piece), which the labels guarantee spans less than half a turn going
// towards increasing theta.
void scan_row(const Raster& r, std::uint32_t v, bool back, double xl, double zl, double xr, double zr) {
    if (back) xl = -xl, zl = -zl, xr = -xr, zr = -zr;  // (z1.b2)
    const bool left_on_axis = xl == 0.0 && zl == 0.0, right_on_axis = xr == 0.0 && zr == 0.0;
    if (left_on_axis && right_on_axis) return;
    // A cut that ends on the axis lies on a line through it, and every ray of the half turn facing
    // the triangle passes through that end (d = 0), as the exact definition counts it: the span
    // then starts (ends) opposite the other end.
    const double xmin = left_on_axis ? -xr : xl, zmin = left_on_axis ? -zr : zl;
    const double xmax = right_on_axis ? -xl : xr, zmax = right_on_axis ? -zl : zr;
    const double theta_min = theta_of(xmin, zmin), theta_max = theta_of(xmax, zmax);
    const long u_begin = column_at(r, xmin, zmin, theta_min);
    long u_end = column_at(r, xmax, zmax, theta_max);
    // Eq. 4.2: theta_max < theta_min means the row crosses the seam. The paper tells a seam
    // crossing by a jump of more than pi; a cut spans less than pi, so an inversion under a
    // quarter turn can only be a cut of (nearly) zero width, whose columns decide it.
    if (theta_min - theta_max > 0.5 * kPi) u_end += long(r.width);
    if (u_begin >= u_end) return;

    // (z3) The cut's line z = alpha x + beta, kept as dz / dx and beta dx so that a cut parallel
    // to the z axis (dx = 0) needs no division: x_u = beta dx / (gamma dx - dz), and likewise with
    // x and z swapped in the other kind of column.
    const double dx = xr - xl, dz = zr - zl, beta_dx = zl * dx - xl * dz;
    float* row = r.depth + std::size_t(v) * r.width;
    const auto depth_test = [&](long u) {
        const ColumnRay& ray = r.rays[std::size_t(u)];
        const double d = std::abs(beta_dx / (ray.a * dx + ray.b * dz)) * ray.secant;
        if (!(d <= 1.0)) return;  // beyond the cylinder wall (or no crossing at all: NaN)
        const float signed_d = float(back ? -d : d);
        if (signed_d > row[u]) row[u] = signed_d;  // (z3-a)
    };
    const long w = long(r.width);
    for (long u = u_begin; u < std::min(u_end, w); ++u) depth_test(u);
    for (long u = std::max(u_begin, w); u < u_end; ++u) depth_test(u - w);
}

// (z1, z2) One triangle, over the rows [row_begin, row_end).
void scan_triangle(const Raster& r, const Point& a, const Point& b, const Point& c, long row_begin, long row_end) {
    if (!std::isfinite(a.x + a.y + a.z + b.x + b.y + b.z + c.x + c.y + c.z)) return;  // NaN or Inf corners
    // (z2.a) Sort by height: the long edge spans all rows, the two short ones meet at `mid`. Most
    // small triangles fall between two rows: they leave here.
    const Point* p[3] = {&a, &b, &c};
    if (p[1]->y < p[0]->y) std::swap(p[0], p[1]);
    if (p[2]->y < p[1]->y) std::swap(p[1], p[2]);
    if (p[1]->y < p[0]->y) std::swap(p[0], p[1]);
    const Point &lo = *p[0], &mid = *p[1], &hi = *p[2];
    const auto [first, last] = rows_between(r, lo.y, hi.y, row_begin, row_end);
    if (first > last) return;

    // (z1) N_xz of the triangle's normal (b - a) x (c - a), the normal the facing rule uses.
    const double e1x = b.x - a.x, e1y = b.y - a.y, e1z = b.z - a.z;
    const double e2x = c.x - a.x, e2y = c.y - a.y, e2z = c.z - a.z;
    const double nx = e1y * e2z - e1z * e2y, nz = e1x * e2y - e1y * e2x;
    if (nx == 0.0 && nz == 0.0) return;  // horizontal: no line perpendicular to the axis sees it
    const double s[3] = {a.x * nx + a.z * nz, b.x * nx + b.z * nz, c.x * nx + c.z * nz};
    const bool any_front = s[0] > 0.0 || s[1] > 0.0 || s[2] > 0.0;
    const bool any_back = s[0] < 0.0 || s[1] < 0.0 || s[2] < 0.0;
    const bool exception = any_front && any_back;  // (z1.c)
    const bool back = any_back && !any_front;      // (z1.b); all >= 0 is (z1.a)

    const Edge long_edge = make_edge(lo, hi), lower = make_edge(lo, mid), upper = make_edge(mid, hi);

    // (z2.a3) Left / right labels. Every cut of a front piece lies on a line N_xz . V = k with
    // k >= 0, along which theta grows in the direction T = (-N_z, N_x); so the long edge is the
    // left one iff the middle vertex lies towards +T of it. This is the paper's comparison of the
    // vertices' thetas at the middle vertex's height, without atan and thus without a seam to
    // correct first (z2.a2). A back piece is turned half a turn, which swaps the labels.
    const Point on_long = cut(long_edge, mid.y);
    const double across = -nz * (mid.x - on_long.x) + nx * (mid.z - on_long.z);
    if (across == 0.0) return;  // no width even at its widest row: degenerate
    const bool long_left_if_front = across > 0.0;

    for (long v = first; v <= last; ++v) {
        const double y = r.row_y[std::size_t(v)];
        const Point q_long = cut(long_edge, y);
        const Point q_short = y < mid.y ? cut(lower, y) : y > mid.y ? cut(upper, y) : mid;
        // An exception triangle's two pieces lie on either side of the horizontal line where
        // V . N_xz changes sign; on a row it has one sign, that of the cut's k.
        const bool row_back = exception ? nx * (q_long.x + q_short.x) + nz * (q_long.z + q_short.z) < 0.0 : back;
        const bool long_left = long_left_if_front != row_back;
        const Point& left = long_left ? q_long : q_short;
        const Point& right = long_left ? q_short : q_long;
        scan_row(r, std::uint32_t(v), row_back, left.x, left.z, right.x, right.z);
    }
}

struct Geometry {
    std::vector<Point> points;  // in the cylinder frame, in double
    const std::vector<std::uint32_t>* triangles = nullptr;

    void scan(const Raster& r, std::size_t f, long row_begin, long row_end) const {
        const std::uint32_t* t = triangles->data() + 3 * f;
        scan_triangle(r, points[t[0]], points[t[1]], points[t[2]], row_begin, row_end);
    }
};

Geometry scanline_geometry(const CylinderMesh& mesh, const CylinderTransform& m) {
    if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0)
        throw geo::InputError("cylinder mesh arrays are not whole triangles / vertices");
    const std::size_t n = mesh.positions.size() / 3;
    for (std::uint32_t i : mesh.triangles)
        if (i >= n) throw geo::InputError("cylinder mesh face names a missing vertex");
    Geometry g;
    g.points.resize(n);
    g.triangles = &mesh.triangles;
    for (std::size_t i = 0; i < n; ++i) {
        const double x = mesh.positions[3 * i], y = mesh.positions[3 * i + 1], z = mesh.positions[3 * i + 2];
        const Point q{double(m[0]) * x + double(m[1]) * y + double(m[2]) * z + double(m[3]),
                      double(m[4]) * x + double(m[5]) * y + double(m[6]) * z + double(m[7]),
                      double(m[8]) * x + double(m[9]) * y + double(m[10]) * z + double(m[11])};
        g.points[i] = q;
    }
    return g;
}

// Runs work(k) for k = 0, 1, ... count - 1 on `threads` threads, each taking the next k.
template <class Work>
void parallel_for(unsigned threads, std::size_t count, const Work& work) {
    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
        for (std::size_t k; (k = next.fetch_add(1)) < count;) work(k);
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
}

// Threads split the image into bands of rows, each band holding the faces that reach into it;
// a pixel is written by one band only, so the result is the single-threaded one bit for bit.
void scan_in_bands(const Raster& r, const Geometry& g, std::size_t faces, unsigned threads) {
    const long height = long(r.height);
    const long band_count = std::min<long>(height, 4L * threads);  // a few per thread, for balance
    const auto band_of_row = [&](long v) { return std::uint32_t(v * band_count / height); };
    const auto band_start = [&](std::size_t b) { return (long(b) * height + band_count - 1) / band_count; };

    // Which bands each face may reach ({1, 0}: none), in chunks of faces over the threads. A row
    // too many only costs a face a visit to a band where scan_triangle finds no row of it.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> reach(faces, {1, 0});
    constexpr std::size_t kChunk = 8192;
    const double h = double(r.height);
    parallel_for(threads, (faces + kChunk - 1) / kChunk, [&](std::size_t chunk) {
        for (std::size_t f = chunk * kChunk; f < std::min(faces, (chunk + 1) * kChunk); ++f) {
            const std::uint32_t* t = g.triangles->data() + 3 * f;
            const double y0 = g.points[t[0]].y, y1 = g.points[t[1]].y, y2 = g.points[t[2]].y;
            // Rows h (1 - y) - 1/2 of the face's ends, one row wider on either side for rounding.
            const double top = h * (1.0 - std::max({y0, y1, y2})) - 1.5;
            const double bottom = h * (1.0 - std::min({y0, y1, y2})) + 0.5;
            if (!(top < h) || !(bottom > 0.0)) continue;  // off the image, or not finite
            reach[f] = {band_of_row(top > 0.0 ? long(top) : 0),
                        band_of_row(bottom < h - 1.0 ? long(bottom) : height - 1)};
        }
    });
    // Counting sort of the faces into their bands.
    std::vector<std::size_t> offsets(std::size_t(band_count) + 1, 0);
    for (const auto& [first, last] : reach)
        for (std::uint32_t b = first; b <= last; ++b) ++offsets[b + 1];
    for (std::size_t b = 0; b < std::size_t(band_count); ++b) offsets[b + 1] += offsets[b];
    std::vector<std::uint32_t> band_faces(offsets.back());
    std::vector<std::size_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t f = 0; f < faces; ++f)
        for (std::uint32_t b = reach[f].first; b <= reach[f].second; ++b) band_faces[fill[b]++] = std::uint32_t(f);

    parallel_for(threads, std::size_t(band_count), [&](std::size_t b) {
        for (std::size_t k = offsets[b]; k < offsets[b + 1]; ++k)
            g.scan(r, band_faces[k], band_start(b), band_start(b + 1));
    });
}

}  // namespace

CylinderImage cylinder_scanline(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                                const CylinderTransform& transform) {
    return cylinder_scanline(mesh, width, height, transform, 0);
}

CylinderImage cylinder_scanline(const CylinderMesh& mesh, std::uint32_t width, std::uint32_t height,
                                const CylinderTransform& transform, unsigned threads) {
    if (width == 0 || height == 0 || width > 65535 || height > 65535)
        throw geo::InputError("cylinder image size must be between 1x1 and 65535x65535");
    const Geometry g = scanline_geometry(mesh, transform);
    std::vector<float> depth(std::size_t(width) * height, kEmpty);
    const Raster r = make_raster(width, height, depth.data());

    const std::size_t faces = mesh.face_count();
    if (threads == 0) {
        const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
        threads = unsigned(std::min(cores, faces / kFacesPerThread));
    }
    threads = std::clamp(threads, 1u, height);
    if (threads <= 1) {
        for (std::size_t f = 0; f < faces; ++f) g.scan(r, f, 0, long(height));
    } else {
        scan_in_bands(r, g, faces, threads);
    }

    CylinderImage image(width, height);
    for (std::size_t i = 0; i < depth.size(); ++i) {
        const bool hit = depth[i] >= -1.0f;
        image.covered[i] = hit;
        image.distance[i] = hit ? depth[i] : 0.0f;
    }
    return image;
}

}  // namespace gimg::passes

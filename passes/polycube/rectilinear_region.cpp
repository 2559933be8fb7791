// Step 2-2: the rectilinear polygon around a plane's contours, by quadtrees (Satoh & Imai
// sec. 2.2). Every quadtree is rooted at one rectangle for all planes, so the layers line up; each
// component of a plane's section (an outer contour and its holes) is refined on its own until it
// meets the stop rule. The union of the cells that meet a region is the same whether interior
// cells stay coarse or not, so a quadtree is kept as the bitmap of its deepest level.
#include "polycube_parts.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace gimg::passes {

namespace {

using polycube::segments_cross;
using Loops = std::vector<const std::vector<glm::dvec2>*>;

bool segment_meets_box(glm::dvec2 a, glm::dvec2 b, glm::dvec2 lo, glm::dvec2 hi) {
    const auto inside = [&](glm::dvec2 p) { return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y; };
    if (inside(a) || inside(b)) return true;
    const glm::dvec2 c[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
    for (int i = 0; i < 4; ++i)
        if (segments_cross(a, b, c[i], c[(i + 1) % 4])) return true;
    return false;
}

// A w x h block of cells of the 2^depth grid, its first cell at (x0, y0).
struct Window {
    int x0 = 0, y0 = 0, w = 0, h = 0;
    std::vector<std::uint8_t> cells;
    std::uint8_t at(int x, int y) const {  // grid coordinates; outside: empty
        x -= x0, y -= y0;
        return x < 0 || y < 0 || x >= w || y >= h ? 0 : cells[std::size_t(y) * w + x];
    }
};

// Components of the cells equal to `value` (the outside counts as empty), joined through edges,
// or also through corners.
std::size_t components(const Window& win, std::uint8_t value, bool corners) {
    const int mw = win.w + 2, mh = win.h + 2;
    std::vector<std::uint8_t> seen(std::size_t(mw) * mh, 0);
    const auto get = [&](int x, int y) { return win.at(x - 1 + win.x0, y - 1 + win.y0); };
    std::size_t count = 0;
    std::vector<int> stack;
    for (int start = 0; start < mw * mh; ++start) {
        if (seen[start] || get(start % mw, start / mw) != value) continue;
        ++count;
        stack.push_back(start);
        seen[start] = 1;
        while (!stack.empty()) {
            const int c = stack.back();
            stack.pop_back();
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    if ((dx == 0 && dy == 0) || (!corners && dx != 0 && dy != 0)) continue;
                    const int x = c % mw + dx, y = c / mw + dy;
                    if (x < 0 || y < 0 || x >= mw || y >= mh) continue;
                    const int k = y * mw + x;
                    if (!seen[k] && get(x, y) == value) seen[k] = 1, stack.push_back(k);
                }
        }
    }
    return count;
}

bool has_checkerboard(const Window& win) {
    for (int y = win.y0 - 1; y < win.y0 + win.h; ++y)
        for (int x = win.x0 - 1; x < win.x0 + win.w; ++x) {
            const std::uint8_t a = win.at(x, y), b = win.at(x + 1, y), c = win.at(x, y + 1), d = win.at(x + 1, y + 1);
            if (a == d && b == c && a != b) return true;
        }
    return false;
}

bool topology_ok(const Window& win, std::size_t pieces, std::size_t holes) {
    const std::size_t fg = components(win, 1, false), bg = components(win, 0, false);
    return fg == pieces && fg == components(win, 1, true) && bg == holes + 1 && bg == components(win, 0, true) &&
           !has_checkerboard(win);
}

// The cells of the 2^depth grid over root that meet the even-odd region of `loops` (each
// segment's cells, and the cells whose centre is inside), in the window around the loops.
Window cells_meeting(const Loops& loops, const Rect& root, int depth) {
    const int n = 1 << depth;
    const glm::dvec2 cell = (root.max - root.min) / double(n);
    const auto clampi = [&](double v) { return std::clamp(int(std::floor(v)), 0, n - 1); };
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto* loop : loops)
        for (const auto& p : *loop) lo = glm::min(lo, p), hi = glm::max(hi, p);
    Window win;
    win.x0 = clampi((lo.x - root.min.x) / cell.x);
    win.y0 = clampi((lo.y - root.min.y) / cell.y);
    win.w = clampi((hi.x - root.min.x) / cell.x) - win.x0 + 1;
    win.h = clampi((hi.y - root.min.y) / cell.y) - win.y0 + 1;
    win.cells.assign(std::size_t(win.w) * win.h, 0);
    for (const auto* loop : loops)
        for (std::size_t i = 0; i < loop->size(); ++i) {
            const glm::dvec2 a = (*loop)[i], b = (*loop)[(i + 1) % loop->size()];
            const int x0 = clampi((std::min(a.x, b.x) - root.min.x) / cell.x),
                      x1 = clampi((std::max(a.x, b.x) - root.min.x) / cell.x),
                      y0 = clampi((std::min(a.y, b.y) - root.min.y) / cell.y),
                      y1 = clampi((std::max(a.y, b.y) - root.min.y) / cell.y);
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    std::uint8_t& c = win.cells[std::size_t(y - win.y0) * win.w + (x - win.x0)];
                    if (c) continue;
                    const glm::dvec2 corner = root.min + glm::dvec2(x, y) * cell;
                    if (segment_meets_box(a, b, corner, corner + cell)) c = 1;
                }
        }
    std::vector<double> xs;
    for (int y = win.y0; y < win.y0 + win.h; ++y) {
        const double yc = root.min.y + (y + 0.5) * cell.y;
        xs.clear();
        for (const auto* loop : loops)
            for (std::size_t i = 0, j = loop->size() - 1; i < loop->size(); j = i++) {
                const glm::dvec2 a = (*loop)[i], b = (*loop)[j];
                if ((a.y > yc) != (b.y > yc)) xs.push_back(a.x + (yc - a.y) * (b.x - a.x) / (b.y - a.y));
            }
        std::sort(xs.begin(), xs.end());
        for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
            const int x0 = std::max(win.x0, int(std::ceil((xs[k] - root.min.x) / cell.x - 0.5))),
                      x1 = std::min(win.x0 + win.w - 1, int(std::floor((xs[k + 1] - root.min.x) / cell.x - 0.5)));
            for (int x = x0; x <= x1; ++x) win.cells[std::size_t(y - win.y0) * win.w + (x - win.x0)] = 1;
        }
    }
    return win;
}

// Pockets the cells enclose (empty cells cut off from the outside) that hold none of the holes
// are filled: a contour folding back on itself closer than a cell does not make a hole.
void fill_pockets(Window& win, const Loops& loops, const Rect& root, int depth) {
    const glm::dvec2 cell = (root.max - root.min) / double(1 << depth);
    std::vector<std::uint8_t> seen(win.cells.size(), 0);
    for (std::size_t start = 0; start < win.cells.size(); ++start) {
        if (win.cells[start] || seen[start]) continue;
        std::vector<std::size_t> pocket{start}, stack{start};
        seen[start] = 1;
        bool open = false, holds_hole = false;
        while (!stack.empty()) {
            const std::size_t c = stack.back();
            stack.pop_back();
            const int cx = int(c % win.w), cy = int(c / win.w);
            if (cx == 0 || cy == 0 || cx == win.w - 1 || cy == win.h - 1) open = true;
            const glm::dvec2 centre = root.min + glm::dvec2(cx + win.x0 + 0.5, cy + win.y0 + 0.5) * cell;
            for (std::size_t h = 1; h < loops.size() && !holds_hole; ++h)
                holds_hole = polycube::point_in_loops({*loops[h]}, centre);
            const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
            for (int d = 0; d < 4; ++d) {
                const int x = cx + dx[d], y = cy + dy[d];
                if (x < 0 || y < 0 || x >= win.w || y >= win.h) continue;
                const std::size_t q = std::size_t(y) * win.w + x;
                if (!win.cells[q] && !seen[q]) seen[q] = 1, stack.push_back(q), pocket.push_back(q);
            }
        }
        if (!open && !holds_hole)
            for (std::size_t c : pocket) win.cells[c] = 1;
    }
}

// Holes narrower than a cell meet no empty cell: each such hole gets the cell whose centre lies
// deepest inside it (with no centre inside, the cell holding the deepest of 16 x 16 points over its
// bounding box), so a thin handle keeps its tunnel.
void open_lost_holes(Window& win, const Loops& loops, const Rect& root, int depth) {
    const glm::dvec2 cell = (root.max - root.min) / double(1 << depth);
    const auto index_of = [&](glm::dvec2 p) -> std::ptrdiff_t {
        const int x = int(std::floor((p.x - root.min.x) / cell.x)) - win.x0,
                  y = int(std::floor((p.y - root.min.y) / cell.y)) - win.y0;
        return x < 0 || y < 0 || x >= win.w || y >= win.h ? -1 : std::ptrdiff_t(y) * win.w + x;
    };
    for (std::size_t h = 1; h < loops.size(); ++h) {
        const auto& hole = *loops[h];
        glm::dvec2 lo(1e300), hi(-1e300), mean(0.0);
        for (const auto& p : hole) lo = glm::min(lo, p), hi = glm::max(hi, p), mean += p;
        mean /= double(hole.size());
        bool has_air = false;
        std::ptrdiff_t best = -1;
        double deepest = -1.0;
        for (int y = std::max(0, int((lo.y - root.min.y) / cell.y) - win.y0);
             y < win.h && root.min.y + (y + win.y0) * cell.y <= hi.y; ++y)
            for (int x = std::max(0, int((lo.x - root.min.x) / cell.x) - win.x0);
                 x < win.w && root.min.x + (x + win.x0) * cell.x <= hi.x; ++x) {
                const glm::dvec2 c = root.min + glm::dvec2(x + win.x0 + 0.5, y + win.y0 + 0.5) * cell;
                if (!polycube::point_in_loops({hole}, c)) continue;
                const std::size_t i = std::size_t(y) * win.w + x;
                if (!win.cells[i]) has_air = true;
                const double d = polycube::distance_to_loop(c, hole);
                if (d > deepest) deepest = d, best = std::ptrdiff_t(i);
            }
        if (has_air) continue;
        if (best < 0) {  // no cell centre inside: the cell holding the point deepest inside
            glm::dvec2 inner = mean;
            double depth_in = polycube::point_in_loops({hole}, mean) ? polycube::distance_to_loop(mean, hole) : -1.0;
            for (int j = 0; j < 16; ++j)
                for (int i = 0; i < 16; ++i) {
                    const glm::dvec2 q = lo + (hi - lo) * glm::dvec2((i + 0.5) / 16.0, (j + 0.5) / 16.0);
                    if (!polycube::point_in_loops({hole}, q)) continue;
                    if (const double d = polycube::distance_to_loop(q, hole); d > depth_in) depth_in = d, inner = q;
                }
            if (depth_in >= 0.0) best = index_of(inner);
        }
        if (best >= 0) win.cells[std::size_t(best)] = 0;
    }
}

double distance_to_loops(glm::dvec2 p, const Loops& loops) {
    double best = 1e300;
    for (const auto* loop : loops) best = std::min(best, polycube::distance_to_loop(p, *loop));
    return best;
}

}  // namespace

RectilinearRegion rectilinear_region(const std::vector<std::vector<glm::dvec2>>& loops, Rect root, double da,
                                     std::uint32_t max_level, std::uint32_t min_depth) {
    RectilinearRegion r;
    r.root = root;
    // Nesting: a loop inside an even number of others bounds a piece, inside an odd number a hole
    // of the innermost loop around it. A piece and its holes are one component. Loops that cross
    // (a surface through itself) can each lie inside the other: a "hole" whose innermost loop is no
    // piece bounds a piece of its own, and the region's topology check then fails.
    std::vector<std::size_t> nesting(loops.size(), 0), parent(loops.size(), loops.size());
    for (std::size_t i = 0; i < loops.size(); ++i) {
        if (loops[i].size() < 3) continue;
        for (std::size_t j = 0; j < loops.size(); ++j)
            if (j != i && loops[j].size() >= 3 && polycube::point_in_loops({loops[j]}, loops[i][0])) {
                ++nesting[i];
                if (parent[i] == loops.size() ||
                    std::abs(polycube::signed_area(loops[j])) < std::abs(polycube::signed_area(loops[parent[i]])))
                    parent[i] = j;
            }
    }
    std::size_t holes = 0;
    std::vector<std::uint8_t> hole(loops.size(), 0);
    for (std::size_t i = 0; i < loops.size(); ++i) {
        if (loops[i].size() < 3) continue;
        hole[i] = nesting[i] % 2 == 1 && parent[i] < loops.size() && nesting[parent[i]] % 2 == 0;
        holes += hole[i];
        r.region_area += (hole[i] ? -1.0 : 1.0) * std::abs(polycube::signed_area(loops[i]));
    }
    std::vector<Loops> parts;  // per component: its outer loop, then its holes
    std::vector<double> part_area;
    std::vector<std::size_t> part_of(loops.size(), 0);
    for (std::size_t i = 0; i < loops.size(); ++i)
        if (loops[i].size() >= 3 && !hole[i]) {
            part_of[i] = parts.size();
            parts.push_back({&loops[i]});
            part_area.push_back(std::abs(polycube::signed_area(loops[i])));
        }
    for (std::size_t i = 0; i < loops.size(); ++i)
        if (hole[i]) {
            parts[part_of[parent[i]]].push_back(&loops[i]);
            part_area[part_of[parent[i]]] -= std::abs(polycube::signed_area(loops[i]));
        }

    // Each component alone: the shallowest depth meeting the stop rule with its own topology.
    const glm::dvec2 size = root.max - root.min;
    std::vector<int> depth(parts.size(), 0);
    std::vector<Window> cells(parts.size());
    const auto refine = [&](std::size_t k, int from) {
        for (int d = from;; ++d) {
            Window w = cells_meeting(parts[k], root, d);
            fill_pockets(w, parts[k], root, d);
            const glm::dvec2 cell = size / double(1 << d);
            const double area = double(std::count(w.cells.begin(), w.cells.end(), 1)) * cell.x * cell.y;
            const double excess = part_area[k] > 0 ? (area - part_area[k]) / part_area[k] : 0.0;
            depth[k] = d;
            cells[k] = std::move(w);
            if (excess < da && topology_ok(cells[k], 1, parts[k].size() - 1)) return;
            if (d >= int(max_level)) {
                if (!topology_ok(cells[k], 1, parts[k].size() - 1)) open_lost_holes(cells[k], parts[k], root, d);
                return;
            }
        }
    };
    for (std::size_t k = 0; k < parts.size(); ++k) refine(k, int(std::min(min_depth, max_level)));

    // Together at the deepest of their depths: components that overlap or touch are refined
    // further; at the deepest level the cells between them go to the nearer one.
    for (;;) {
        int top = 0;
        for (int d : depth) top = std::max(top, d);
        const int n = 1 << top;
        std::vector<std::int32_t> owner(std::size_t(n) * n, -1);  // cell -> component
        std::vector<std::uint8_t> conflicted(parts.size(), 0);
        std::vector<std::size_t> contested;
        for (std::size_t k = 0; k < parts.size(); ++k) {
            const int shift = top - depth[k];
            const Window& w = cells[k];
            for (int y = 0; y < w.h; ++y)
                for (int x = 0; x < w.w; ++x) {
                    if (!w.cells[std::size_t(y) * w.w + x]) continue;
                    for (int sy = 0; sy < (1 << shift); ++sy)
                        for (int sx = 0; sx < (1 << shift); ++sx) {
                            const std::size_t c =
                                std::size_t(((w.y0 + y) << shift) + sy) * n + (((w.x0 + x) << shift) + sx);
                            if (owner[c] < 0) {
                                owner[c] = std::int32_t(k);
                            } else if (owner[c] != std::int32_t(k)) {
                                conflicted[k] = conflicted[owner[c]] = 1;
                                contested.push_back(c);
                            }
                        }
                }
        }
        for (std::size_t c = 0; c < owner.size(); ++c) {
            const std::int32_t k = owner[c];
            if (k < 0) continue;
            const int cx = int(c % n), cy = int(c / n);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = cx + dx, y = cy + dy;
                    if (x < 0 || y < 0 || x >= n || y >= n) continue;
                    const std::int32_t o = owner[std::size_t(y) * n + x];
                    if (o >= 0 && o != k) conflicted[k] = conflicted[o] = 1;
                }
        }
        bool refined = false;
        for (std::size_t k = 0; k < parts.size(); ++k)
            if (conflicted[k] && depth[k] < int(max_level)) refine(k, depth[k] + 1), refined = true;
        if (refined) continue;

        // Settle what is left: contested cells to the nearer component, then cells touching
        // another component's given up by the farther side.
        const glm::dvec2 cell = size / double(n);
        const auto centre = [&](std::size_t c) {
            return root.min + glm::dvec2(double(c % n) + 0.5, double(c / n) + 0.5) * cell;
        };
        for (std::size_t k = 0; k < parts.size(); ++k) {  // contested: re-run the claims by distance
            if (!conflicted[k]) continue;
            const int shift = top - depth[k];
            const Window& w = cells[k];
            for (int y = 0; y < w.h; ++y)
                for (int x = 0; x < w.w; ++x)
                    if (w.cells[std::size_t(y) * w.w + x])
                        for (int sy = 0; sy < (1 << shift); ++sy)
                            for (int sx = 0; sx < (1 << shift); ++sx) {
                                const std::size_t c =
                                    std::size_t(((w.y0 + y) << shift) + sy) * n + (((w.x0 + x) << shift) + sx);
                                std::int32_t& o = owner[c];
                                if (o >= 0 && o != std::int32_t(k) &&
                                    distance_to_loops(centre(c), parts[k]) < distance_to_loops(centre(c), parts[o]))
                                    o = std::int32_t(k);
                            }
        }
        std::size_t carved = 0;
        for (bool changed = true; changed;) {
            changed = false;
            for (std::size_t c = 0; c < owner.size(); ++c) {
                if (owner[c] < 0 || !conflicted[owner[c]]) continue;
                const int cx = int(c % n), cy = int(c / n);
                bool drop = false;
                for (int dy = -1; dy <= 1 && !drop; ++dy)
                    for (int dx = -1; dx <= 1 && !drop; ++dx) {
                        const int x = cx + dx, y = cy + dy;
                        if (x < 0 || y < 0 || x >= n || y >= n) continue;
                        const std::size_t q = std::size_t(y) * n + x;
                        if (owner[q] < 0 || owner[q] == owner[c]) continue;
                        drop = distance_to_loops(centre(c), parts[owner[c]]) >=
                               distance_to_loops(centre(q), parts[owner[q]]);
                    }
                if (drop) owner[c] = -1, ++carved, changed = true;
            }
        }
        r.depth = std::uint32_t(top);
        r.cells.assign(std::size_t(n) * n, 0);
        for (std::size_t c = 0; c < owner.size(); ++c) r.cells[c] = owner[c] >= 0;
        r.owner = std::move(owner);
        r.component_depth.assign(depth.begin(), depth.end());
        r.component_of_loop.assign(loops.size(), -1);
        for (std::size_t i = 0; i < loops.size(); ++i)
            if (loops[i].size() >= 3) r.component_of_loop[i] = std::int32_t(part_of[hole[i] ? parent[i] : i]);
        r.area = double(std::count(r.cells.begin(), r.cells.end(), 1)) * cell.x * cell.y;
        r.carved = carved + contested.size();
        Window all;
        all.w = all.h = n;
        all.cells = r.cells;
        r.topology_ok = topology_ok(all, parts.size(), holes);
        return r;
    }
}

namespace polycube {

Layers stacked_regions(const std::vector<Contour>& contours, const std::vector<double>& plane_z, const geo::Bounds& box,
                       double da, std::uint32_t max_level, const JoinedContours& joined, double& excess,
                       std::size_t& carved) {
    Rect root{{box.min.x, box.min.y}, {box.max.x, box.max.y}};
    for (const auto& c : contours)
        for (const auto& p : c.closed) root.min = glm::min(root.min, p), root.max = glm::max(root.max, p);
    const std::size_t planes = plane_z.size();
    std::vector<std::vector<std::vector<glm::dvec2>>> loops(planes);
    std::vector<std::size_t> loop_of(contours.size());  // contour -> its loop on its plane
    for (std::size_t c = 0; c < contours.size(); ++c) {
        loop_of[c] = loops[contours[c].plane].size();
        loops[contours[c].plane].push_back(contours[c].closed);
    }
    std::vector<RectilinearRegion> regions(planes);
    std::vector<std::uint32_t> min_depth(planes, 0);
    std::vector<std::uint8_t> stale(planes, 1);
    std::uint32_t depth = 0;
    std::vector<std::vector<std::int32_t>> owner(planes);  // per plane, per cell at `depth`: its component
    // Per slab between planes p and p + 1, the component pairs a mesh piece joins.
    const auto allowed = [&](std::size_t p) {
        std::set<std::pair<std::int32_t, std::int32_t>> pairs;
        if (p + 1 < joined.size())
            for (const auto& [lower, upper] : joined[p + 1])
                pairs.insert(
                    {regions[p].component_of_loop[loop_of[lower]], regions[p + 1].component_of_loop[loop_of[upper]]});
        return pairs;
    };
    struct Touch {
        std::size_t plane;  // the lower layer; the upper is plane + 1
        std::int32_t lower, upper;
        std::size_t lower_cell, upper_cell;
    };
    // Cells of neighbouring layers that overlap or meet at an edge or corner (the surface joins
    // them there) while no mesh piece joins their components.
    const auto touches = [&] {
        std::vector<Touch> found;
        const int n = 1 << depth;
        for (std::size_t p = 0; p + 1 < planes; ++p) {
            const auto ok = allowed(p);
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const std::size_t c = std::size_t(y) * n + x;
                    const std::int32_t a = owner[p][c];
                    if (a < 0) continue;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const int qx = x + dx, qy = y + dy;
                            if (qx < 0 || qy < 0 || qx >= n || qy >= n) continue;
                            const std::size_t q = std::size_t(qy) * n + qx;
                            const std::int32_t b = owner[p + 1][q];
                            if (b >= 0 && !ok.count({a, b})) found.push_back({p, a, b, c, q});
                        }
                }
        }
        return found;
    };
    carved = 0;
    for (;;) {
        for (std::size_t p = 0; p < planes; ++p)
            if (stale[p]) regions[p] = rectilinear_region(loops[p], root, da, max_level, min_depth[p]), stale[p] = 0;
        depth = 0;
        for (const auto& r : regions) depth = std::max(depth, r.depth);
        const int n = 1 << depth;
        for (std::size_t p = 0; p < planes; ++p) {
            const auto& r = regions[p];
            const int shift = int(depth - r.depth), rn = 1 << r.depth;
            owner[p].assign(std::size_t(n) * n, -1);
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x)
                    owner[p][std::size_t(y) * n + x] = r.owner[std::size_t(y >> shift) * rn + (x >> shift)];
        }
        std::vector<Touch> found = touches();
        if (found.empty()) break;
        // Components coarser than max_level refine further and the layers are compared again.
        bool refined = false;
        for (const Touch& t : found)
            for (const auto& [p, k] : {std::pair{t.plane, t.lower}, std::pair{t.plane + 1, t.upper}}) {
                const std::uint32_t d = regions[p].component_depth[std::size_t(k)];
                if (d < max_level && min_depth[p] < d + 1) min_depth[p] = d + 1, stale[p] = 1, refined = true;
            }
        if (refined) continue;
        // At max_level: of each touching pair, the cell farther from its own contours is given up.
        const glm::dvec2 cell = (root.max - root.min) / double(n);
        const auto distance = [&](std::size_t p, std::int32_t k, std::size_t c) {
            const glm::dvec2 centre = root.min + glm::dvec2(double(c % n) + 0.5, double(c / n) + 0.5) * cell;
            double best = 1e300;
            for (std::size_t l = 0; l < loops[p].size(); ++l)
                if (regions[p].component_of_loop[l] == k)
                    best = std::min(best, polycube::distance_to_loop(centre, loops[p][l]));
            return best;
        };
        for (; !found.empty(); found = touches())
            for (const Touch& t : found) {
                if (owner[t.plane][t.lower_cell] != t.lower || owner[t.plane + 1][t.upper_cell] != t.upper) continue;
                if (distance(t.plane, t.lower, t.lower_cell) >= distance(t.plane + 1, t.upper, t.upper_cell))
                    owner[t.plane][t.lower_cell] = -1;
                else
                    owner[t.plane + 1][t.upper_cell] = -1;
                ++carved;
            }
        break;
    }
    std::vector<std::int32_t> component(contours.size());
    for (std::size_t c = 0; c < contours.size(); ++c)
        component[c] = regions[contours[c].plane].component_of_loop[loop_of[c]];
    const std::size_t opened = open_air_passages(owner, 1 << depth, root, contours, component, joined);
    excess = 0.0;
    for (const auto& r : regions) excess += r.excess();
    Layers layers;
    layers.root = root;
    layers.depth = depth;
    layers.plane_z = plane_z;
    layers.opened = opened;
    layers.bottom = box.min.z;
    layers.top = box.max.z;
    for (const auto& o : owner) {
        std::vector<std::uint8_t> cells(o.size());
        for (std::size_t c = 0; c < o.size(); ++c) cells[c] = o[c] >= 0;
        layers.cells.push_back(std::move(cells));
    }
    for (std::size_t p = 0; p < planes; ++p) layers.joins.push_back(allowed(p));
    layers.owner = std::move(owner);
    return layers;
}

}  // namespace polycube

}  // namespace gimg::passes

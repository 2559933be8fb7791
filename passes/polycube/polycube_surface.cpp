// Step 2-3: the rectilinear layers stacked into one closed orthogonal polyhedron: side walls
// between the mid-planes, and top and bottom faces Q_{i-1} xor Q_i at each mid-plane.
#include "polycube_parts.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <functional>
#include <unordered_map>

namespace gimg::passes {

namespace polycube {

namespace {

// Manifold 2x2x2 blocks (bit = dx + 2 dy + 4 dz): the full and the empty voxels each joined
// through faces inside the block, so the surface around the corner is one disk.
std::array<bool, 256> manifold_blocks() {
    std::array<bool, 256> ok{};
    for (int mask = 0; mask < 256; ++mask) {
        bool good = true;
        for (int value = 0; value < 2 && good; ++value) {
            int members = 0, first = -1;
            for (int b = 0; b < 8; ++b)
                if (((mask >> b) & 1) == value) {
                    ++members;
                    if (first < 0) first = b;
                }
            if (members == 0) continue;
            int reached = 1 << first, grown = 0;
            while (grown != reached) {
                grown = reached;
                for (int b = 0; b < 8; ++b)
                    if ((reached >> b) & 1)
                        for (int axis = 0; axis < 3; ++axis) {
                            const int c = b ^ (1 << axis);
                            if (((mask >> c) & 1) == value) reached |= 1 << c;
                        }
            }
            good = __builtin_popcount(unsigned(reached)) == members;
        }
        ok[mask] = good;
    }
    return ok;
}

}  // namespace

std::size_t make_manifold(Layers& layers) {
    static const std::array<bool, 256> ok = manifold_blocks();
    const int n = 1 << layers.depth;
    const int count = int(layers.cells.size());
    std::size_t filled = 0;
    // A voxel: layer l (-1 and count are the empty outside), cell (x, y) (outside the grid: empty).
    const auto at = [&](int l, int x, int y) -> std::uint8_t {
        if (l < 0 || l >= count || x < 0 || y < 0 || x >= n || y >= n) return 0;
        return layers.cells[l][std::size_t(y) * n + x];
    };
    // Per layer, its pieces (cells joined through edges or corners): a fill must not join two.
    std::vector<std::vector<std::int32_t>> label(count);
    const auto relabel = [&](int l) {
        auto& lab = label[l];
        lab.assign(std::size_t(n) * n, -1);
        std::int32_t next = 0;
        std::vector<int> stack;
        for (int start = 0; start < n * n; ++start) {
            if (!layers.cells[l][start] || lab[start] >= 0) continue;
            lab[start] = next;
            stack.push_back(start);
            while (!stack.empty()) {
                const int c = stack.back();
                stack.pop_back();
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int x = c % n + dx, y = c / n + dy;
                        if (x < 0 || y < 0 || x >= n || y >= n) continue;
                        const int q = y * n + x;
                        if (layers.cells[l][q] && lab[q] < 0) lab[q] = next, stack.push_back(q);
                    }
            }
            ++next;
        }
    };
    const auto joins_pieces = [&](int l, int cx, int cy) {
        std::int32_t seen = -1;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int x = cx + dx, y = cy + dy;
                if (x < 0 || y < 0 || x >= n || y >= n || !layers.cells[l][std::size_t(y) * n + x]) continue;
                const std::int32_t k = label[l][std::size_t(y) * n + x];
                if (seen >= 0 && k != seen) return true;
                seen = k;
            }
        return false;
    };
    // Whether a fill at (l, cx, cy) could cut the layer's air in two (close an air passage into a
    // pocket): its empty edge neighbours fall into more than one group joined around its corners.
    const auto splits_air = [&](int l, int cx, int cy) {
        const int ex[4] = {0, 1, 0, -1}, ey[4] = {-1, 0, 1, 0};
        bool empty[4];
        int count_empty = 0;
        for (int k = 0; k < 4; ++k) count_empty += empty[k] = !at(l, cx + ex[k], cy + ey[k]);
        if (count_empty < 2) return false;
        int groups = 0;
        for (int k = 0; k < 4; ++k) {
            const int j = (k + 1) % 4;  // the next edge neighbour round the ring, and the corner between
            const bool corner = !at(l, cx + ex[k] + ex[j], cy + ey[k] + ey[j]);
            if (empty[k] && !(empty[j] && corner)) ++groups;
        }
        return groups > 1;
    };
    // The component a fill at (l, cx, cy) would join (a neighbour's in its layer), and whether it
    // would touch a component of the layer above or below that the mesh does not join to it.
    const bool owned = layers.owner.size() == layers.cells.size();
    const auto component_for = [&](int l, int cx, int cy) {
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int x = cx + dx, y = cy + dy;
                if (x >= 0 && y >= 0 && x < n && y < n && layers.owner[l][std::size_t(y) * n + x] >= 0)
                    return layers.owner[l][std::size_t(y) * n + x];
            }
        return std::int32_t(-1);
    };
    const auto touches_foreign = [&](int l, int cx, int cy) {
        if (!owned) return false;
        const std::int32_t a = component_for(l, cx, cy);
        if (a < 0) return false;
        for (const int m : {l - 1, l + 1}) {
            if (m < 0 || m >= count) continue;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = cx + dx, y = cy + dy;
                    if (x < 0 || y < 0 || x >= n || y >= n) continue;
                    const std::int32_t b = layers.owner[m][std::size_t(y) * n + x];
                    if (b >= 0 && !(m < l ? layers.joins[m].count({b, a}) : layers.joins[l].count({a, b}))) return true;
                }
        }
        return false;
    };
    for (int pass = 0; pass < 64; ++pass) {
        bool changed = false;
        for (int l = 0; l < count; ++l) relabel(l);
        // Blocks at every mid-plane (lower layer l - 1, upper l) and inside every layer (l, l).
        for (int b = 0; b <= 2 * count; ++b) {
            const int lower = b % 2 ? b / 2 : b / 2 - 1, upper = b / 2;
            for (int y = 0; y <= n; ++y)
                for (int x = 0; x <= n; ++x) {
                    int mask = 0;
                    for (int bit = 0; bit < 8; ++bit)
                        if (at(bit & 4 ? upper : lower, x - 1 + (bit & 1), y - 1 + ((bit >> 1) & 1))) mask |= 1 << bit;
                    if (ok[mask]) continue;
                    // Fill the empty voxel inside the grid that leaves the block manifold, else the one
                    // with the most full face neighbours in the block.
                    int best = -1, best_score = -1;
                    for (int bit = 0; bit < 8; ++bit) {
                        if ((mask >> bit) & 1) continue;
                        const int l = bit & 4 ? upper : lower, cx = x - 1 + (bit & 1), cy = y - 1 + ((bit >> 1) & 1);
                        if (l < 0 || l >= count || cx < 0 || cy < 0 || cx >= n || cy >= n) continue;
                        int m = mask | (1 << bit);
                        if (lower == upper) m |= (bit & 4) ? (1 << (bit - 4)) : (1 << (bit + 4));
                        int score =
                            (ok[m] ? 100 : 0) +
                            (joins_pieces(l, cx, cy) || touches_foreign(l, cx, cy) || splits_air(l, cx, cy) ? -1000
                                                                                                            : 0);
                        for (int axis = 0; axis < 3; ++axis) score += (mask >> (bit ^ (1 << axis))) & 1;
                        if (score > best_score) best_score = score, best = bit;
                    }
                    if (best < 0) continue;
                    const int l = best & 4 ? upper : lower;
                    const int fx = x - 1 + (best & 1), fy = y - 1 + ((best >> 1) & 1);
                    if (best_score < 0) {
                        // Every fill would join two pieces of a layer: give up a full voxel of the
                        // block instead, one with the fewest full face neighbours there.
                        int drop = -1, drop_score = 1 << 20;
                        for (int bit = 0; bit < 8; ++bit) {
                            if (!((mask >> bit) & 1)) continue;
                            int score = 0;
                            for (int axis = 0; axis < 3; ++axis) score += (mask >> (bit ^ (1 << axis))) & 1;
                            if (score < drop_score) drop_score = score, drop = bit;
                        }
                        const int dl = drop & 4 ? upper : lower;
                        const std::size_t dc = std::size_t(y - 1 + ((drop >> 1) & 1)) * n + x - 1 + (drop & 1);
                        layers.cells[dl][dc] = 0;
                        if (owned) layers.owner[dl][dc] = -1;
                        ++filled;
                        changed = true;
                        continue;
                    }
                    if (owned) layers.owner[l][std::size_t(fy) * n + fx] = component_for(l, fx, fy);
                    layers.cells[l][std::size_t(fy) * n + fx] = 1;
                    label[l][std::size_t(fy) * n + fx] = [&] {
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                const int xx = fx + dx, yy = fy + dy;
                                if (xx >= 0 && yy >= 0 && xx < n && yy < n && label[l][std::size_t(yy) * n + xx] >= 0)
                                    return label[l][std::size_t(yy) * n + xx];
                            }
                        return std::int32_t(-2);
                    }();
                    ++filled;
                    changed = true;
                }
        }
        if (!changed) break;
    }
    return filled;
}

std::uint8_t face_axis_index(int axis, bool positive) { return std::uint8_t(2 * axis + (positive ? 0 : 1)); }

PolycubeSurface polycube_surface(const Layers& layers) {
    const int n = 1 << layers.depth;
    const int count = int(layers.cells.size());
    const glm::dvec2 cell = (layers.root.max - layers.root.min) / double(n);
    const double cell_size = 0.5 * (cell.x + cell.y);
    // Heights: every layer from its bottom through its plane to its top, in rows about a cell tall.
    std::vector<double> mids(count + 1);
    mids[0] = layers.bottom;
    mids[count] = layers.top;
    for (int i = 1; i < count; ++i) mids[i] = 0.5 * (layers.plane_z[i - 1] + layers.plane_z[i]);
    std::vector<double> heights;
    std::vector<std::vector<std::uint32_t>> layer_rows(count);  // height indices of each layer, bottom to top
    std::vector<std::uint32_t> plane_height(count);
    for (int i = 0; i < count; ++i) {
        const double z[3] = {mids[i], layers.plane_z[i], mids[i + 1]};
        if (heights.empty()) heights.push_back(z[0]);
        layer_rows[i].push_back(std::uint32_t(heights.size() - 1));
        for (int half = 0; half < 2; ++half) {
            const int rows = std::clamp(int(std::lround((z[half + 1] - z[half]) / (4.0 * cell_size))), 1, 2);
            for (int r = 1; r <= rows; ++r) {
                heights.push_back(r == rows ? z[half + 1] : z[half] + (z[half + 1] - z[half]) * r / rows);
                layer_rows[i].push_back(std::uint32_t(heights.size() - 1));
            }
            if (half == 0) plane_height[i] = std::uint32_t(heights.size() - 1);
        }
    }

    PolycubeSurface s;
    std::unordered_map<std::uint64_t, std::uint32_t> ids;
    const auto vertex = [&](int x, int y, std::uint32_t h) {
        const std::uint64_t key = (std::uint64_t(h) << 40) | (std::uint64_t(y) << 20) | std::uint64_t(x);
        const auto [it, added] = ids.emplace(key, std::uint32_t(s.mesh.positions.size()));
        if (added)
            s.mesh.positions.push_back({layers.root.min.x + x * cell.x, layers.root.min.y + y * cell.y, heights[h]});
        return it->second;
    };
    // A quad a, b, c, d counter-clockwise from outside.
    const auto quad = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d, std::uint8_t axis,
                          std::uint32_t slab) {
        s.mesh.triangles.push_back({a, b, c});
        s.mesh.triangles.push_back({a, c, d});
        s.axis.insert(s.axis.end(), {axis, axis});
        s.slab.insert(s.slab.end(), {slab, slab});
    };
    const auto full = [&](int l, int x, int y) -> bool {
        if (l < 0 || l >= count || x < 0 || y < 0 || x >= n || y >= n) return false;
        return layers.cells[l][std::size_t(y) * n + x] != 0;
    };
    // Horizontal faces at mid-plane m (between layer m - 1 and layer m): the symmetric difference,
    // as the leaves of a quadtree (squares of one orientation), each fanned from its centre through
    // every vertex on its sides, so nothing meets a side in the middle of an edge.
    struct Leaf {
        int x, y, size;
        bool up;
        std::uint32_t h, slab;
    };
    std::vector<Leaf> leaves;
    for (int m = 0; m <= count; ++m) {
        const std::uint32_t h = m < count ? layer_rows[m].front() : layer_rows[count - 1].back();
        // 0: none, 1: top of layer m - 1 (+z), 2: bottom of layer m (-z)
        const auto kind = [&](int x, int y) {
            return full(m - 1, x, y) == full(m, x, y) ? 0 : full(m - 1, x, y) ? 1 : 2;
        };
        const std::function<void(int, int, int)> split = [&](int x, int y, int size) {
            const int k = kind(x, y);
            bool uniform = true;
            for (int yy = y; yy < y + size && uniform; ++yy)
                for (int xx = x; xx < x + size && uniform; ++xx) uniform = kind(xx, yy) == k;
            if (uniform) {
                if (k) leaves.push_back({x, y, size, k == 1, h, std::uint32_t(m)});
                return;
            }
            const int half = size / 2;
            for (int q = 0; q < 4; ++q) split(x + (q & 1) * half, y + (q >> 1) * half, half);
        };
        split(0, 0, n);
    }
    for (const Leaf& l : leaves)
        for (int q = 0; q < 4; ++q) vertex(l.x + (q & 1) * l.size, l.y + (q >> 1) * l.size, l.h);
    // Side walls: straight runs of cell edges between a full and an empty cell of one layer, each
    // run one strip per row, its ends registered at every row first so neighbours see them.
    struct Run {
        int layer, fixed, from, to;  // grid line `fixed`, from `from` to `to` along it (either way)
        bool along_x;                // the run goes along x (a y wall) or along y (an x wall)
        std::uint8_t axis;
    };
    std::vector<Run> runs;
    for (int l = 0; l < count; ++l)
        for (int dir = 0; dir < 4; ++dir) {
            // dir 0: +x walls, 1: -x, 2: +y, 3: -y
            for (int line = 0; line < n; ++line) {
                int start = -1;
                for (int t = 0; t <= n; ++t) {
                    bool wall = false;
                    if (t < n) {
                        const int x = dir < 2 ? line : t, y = dir < 2 ? t : line;
                        const int ox = dir == 0 ? 1 : dir == 1 ? -1 : 0, oy = dir == 2 ? 1 : dir == 3 ? -1 : 0;
                        wall = full(l, x, y) && !full(l, x + ox, y + oy);
                    }
                    if (wall && start < 0) start = t;
                    if (!wall && start >= 0) {
                        const int fixed = dir == 0 || dir == 2 ? line + 1 : line;
                        // Counter-clockwise from outside: +x along +y, -x along -y, +y along -x, -y along +x.
                        const bool forward = dir == 0 || dir == 3;
                        runs.push_back({l, fixed, forward ? start : t, forward ? t : start, dir >= 2,
                                        face_axis_index(dir / 2, dir % 2 == 0)});
                        start = -1;
                    }
                }
            }
        }
    const auto run_point = [](const Run& r, int t) {
        return r.along_x ? std::pair{t, r.fixed} : std::pair{r.fixed, t};
    };
    // Points along each run about a row apart as well, so its strips are cut into triangles of
    // moderate aspect (the map's Tutte solves want no needles).
    std::vector<int> spacing(count, 1);
    for (int l = 0; l < count; ++l) {
        const auto& rows = layer_rows[l];
        const double row = (heights[rows.back()] - heights[rows.front()]) / double(rows.size() - 1);
        spacing[l] = std::max(1, int(std::lround(row / cell_size)));
    }
    for (const Run& r : runs) {
        const int lo = std::min(r.from, r.to), hi = std::max(r.from, r.to);
        for (std::uint32_t h : layer_rows[r.layer])
            for (int t = lo; t <= hi; ++t)
                if (t == lo || t == hi || t % spacing[r.layer] == 0)
                    vertex(run_point(r, t).first, run_point(r, t).second, h);
    }
    const auto key_of = [](int x, int y, std::uint32_t h) {
        return (std::uint64_t(h) << 40) | (std::uint64_t(y) << 20) | std::uint64_t(x);
    };
    for (const Run& r : runs) {
        const auto& rows = layer_rows[r.layer];
        const int step = r.to > r.from ? 1 : -1;
        std::vector<std::vector<std::uint32_t>> at_height(rows.size());
        for (std::size_t k = 0; k < rows.size(); ++k)
            for (int t = r.from;; t += step) {
                const auto [x, y] = run_point(r, t);
                const auto it = ids.find(key_of(x, y, rows[k]));
                if (it != ids.end()) at_height[k].push_back(it->second);
                if (t == r.to) break;
            }
        const auto along = [&](std::uint32_t v) {
            const glm::dvec3 p = s.mesh.positions[v];
            return double(step) * (r.along_x ? p.x : p.y);
        };
        for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
            const std::uint32_t slab =
                rows[k + 1] <= plane_height[r.layer] ? std::uint32_t(r.layer) : std::uint32_t(r.layer + 1);
            const auto& b = at_height[k];
            const auto& t = at_height[k + 1];
            std::size_t i = 0, j = 0;
            while (i + 1 < b.size() || j + 1 < t.size()) {
                const bool bottom = j + 1 >= t.size() || (i + 1 < b.size() && along(b[i + 1]) <= along(t[j + 1]));
                if (bottom) {
                    s.mesh.triangles.push_back({b[i], b[i + 1], t[j]});
                    ++i;
                } else {
                    s.mesh.triangles.push_back({b[i], t[j + 1], t[j]});
                    ++j;
                }
                s.axis.push_back(r.axis);
                s.slab.push_back(slab);
            }
        }
    }
    for (const Leaf& l : leaves) {
        // The sides counter-clockwise from below-left, seen from +z.
        std::vector<std::uint32_t> ring;
        const int cx[4] = {l.x, l.x + l.size, l.x + l.size, l.x}, cy[4] = {l.y, l.y, l.y + l.size, l.y + l.size};
        for (int side = 0; side < 4; ++side) {
            const int dx = (cx[(side + 1) % 4] - cx[side]) / l.size, dy = (cy[(side + 1) % 4] - cy[side]) / l.size;
            for (int step = 0; step < l.size; ++step) {
                const int x = cx[side] + dx * step, y = cy[side] + dy * step;
                const std::uint64_t key = (std::uint64_t(l.h) << 40) | (std::uint64_t(y) << 20) | std::uint64_t(x);
                if (ids.count(key)) ring.push_back(ids.at(key));
            }
        }
        const std::uint8_t axis = face_axis_index(2, l.up);
        if (!l.up) std::reverse(ring.begin(), ring.end());
        if (ring.size() == 4) {
            quad(ring[0], ring[1], ring[2], ring[3], axis, l.slab);
            continue;
        }
        const std::uint32_t centre = std::uint32_t(s.mesh.positions.size());
        s.mesh.positions.push_back({layers.root.min.x + (l.x + 0.5 * l.size) * cell.x,
                                    layers.root.min.y + (l.y + 0.5 * l.size) * cell.y, heights[l.h]});
        for (std::size_t i = 0; i < ring.size(); ++i) {
            s.mesh.triangles.push_back({centre, ring[i], ring[(i + 1) % ring.size()]});
            s.axis.push_back(axis);
            s.slab.push_back(l.slab);
        }
    }
    // The walls' loops at each plane: cell edges with a full cell on the left, seen from above.
    s.loops.resize(count);
    for (int l = 0; l < count; ++l) {
        std::map<std::pair<int, int>, std::pair<int, int>> next;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                if (!full(l, x, y)) continue;
                if (!full(l, x, y - 1)) next[{x, y}] = {x + 1, y};
                if (!full(l, x + 1, y)) next[{x + 1, y}] = {x + 1, y + 1};
                if (!full(l, x, y + 1)) next[{x + 1, y + 1}] = {x, y + 1};
                if (!full(l, x - 1, y)) next[{x, y + 1}] = {x, y};
            }
        std::map<std::pair<int, int>, bool> seen;
        for (const auto& [start, unused] : next) {
            if (seen[start]) continue;
            std::vector<std::uint32_t> loop;
            auto p = start;
            while (!seen[p]) {
                seen[p] = true;
                const auto it = ids.find(key_of(p.first, p.second, plane_height[l]));
                if (it != ids.end()) loop.push_back(it->second);
                p = next.at(p);
            }
            s.loops[l].push_back(std::move(loop));
        }
    }
    // Polycube faces: triangles of one axis joined across edges; corners: where three faces meet.
    const std::vector<std::uint32_t> root =
        join_across_edges(s.mesh.triangles, [&](std::uint32_t f, std::uint32_t g) { return s.axis[f] == s.axis[g]; });
    std::vector<std::vector<std::uint32_t>> vertex_faces(s.mesh.positions.size());
    for (std::uint32_t f = 0; f < s.mesh.triangles.size(); ++f) {
        if (root[f] == f) ++s.faces;
        for (int k = 0; k < 3; ++k) vertex_faces[s.mesh.triangles[f][k]].push_back(root[f]);
    }
    for (auto& v : vertex_faces) {
        std::sort(v.begin(), v.end());
        if (std::unique(v.begin(), v.end()) - v.begin() >= 3) ++s.corners;
    }
    return s;
}

}  // namespace polycube

std::uint8_t axis_of(const glm::dvec3& n) {
    const glm::dvec3 a = glm::abs(n);
    const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
    return std::uint8_t(2 * axis + (n[axis] >= 0.0 ? 0 : 1));
}

}  // namespace gimg::passes

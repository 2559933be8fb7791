// Passages for enclosed air (step 2-2 after the layers are stacked). A hole of a plane's section is
// air the layer encloses; the mesh says where that air goes: a pit that opens sideways between two
// planes shows as a hole on one plane and as nothing (or a notch) on the next, and the mesh's slab
// piece joins the hole's contour to a contour of the next plane. The layers cannot see the opening
// when it lies between the planes, so the hole's air stays a void (a polycube in several pieces).
// Here such air gets a passage: a corridor of cells opened in the next layer, from over the hole to
// the air beside the contour the mesh joins it to, through one component of that layer only, never
// splitting it nor meeting any other air.
#include "polycube_parts.h"

#include <algorithm>
#include <deque>
#include <limits>
#include <numeric>

namespace gimg::passes::polycube {

namespace {

constexpr int kOutside = 0;  // air label of the air joined to the grid's border
constexpr std::int32_t kUnset = -2;

// Calls f(q) for each edge neighbour q of cell c inside the n x n grid.
template <class F>
void for_each_neighbour(std::size_t c, int n, const F& f) {
    const int x = int(c % n), y = int(c / n);
    if (x + 1 < n) f(c + 1);
    if (x > 0) f(c - 1);
    if (y + 1 < n) f(c + std::size_t(n));
    if (y > 0) f(c - std::size_t(n));
}

// Gives `value` to every cell 4-connected to `start` through unset cells that `member` takes.
template <class Member>
void flood(std::size_t start, int n, std::vector<std::int32_t>& label, std::int32_t value, const Member& member) {
    std::vector<std::size_t> stack{start};
    label[start] = value;
    while (!stack.empty()) {
        const std::size_t c = stack.back();
        stack.pop_back();
        for_each_neighbour(c, n, [&](std::size_t q) {
            if (label[q] == kUnset && member(q)) label[q] = value, stack.push_back(q);
        });
    }
}

// 4-connected air components of one layer; the border's air is kOutside, the others 1, 2, ...;
// material cells -1.
std::vector<std::int32_t> air_labels(const std::vector<std::int32_t>& owner, int n) {
    std::vector<std::int32_t> label(owner.size(), kUnset);
    const auto air = [&](std::size_t q) { return owner[q] < 0; };
    for (std::size_t c = 0; c < owner.size(); ++c)
        if (owner[c] >= 0) label[c] = -1;
    for (int i = 0; i < n; ++i)
        for (const std::size_t c :
             {std::size_t(i), std::size_t(n - 1) * n + i, std::size_t(i) * n, std::size_t(i) * n + n - 1})
            if (label[c] == kUnset) flood(c, n, label, kOutside, air);
    std::int32_t next = 1;
    for (std::size_t c = 0; c < owner.size(); ++c)
        if (label[c] == kUnset) flood(c, n, label, next++, air);
    return label;
}

// Whether the cells of component k in `owner` are 4-connected.
bool connected(const std::vector<std::int32_t>& owner, int n, std::int32_t k) {
    std::vector<std::int32_t> label(owner.size(), kUnset);
    const auto first = std::find(owner.begin(), owner.end(), k);
    if (first == owner.end()) return true;
    flood(std::size_t(first - owner.begin()), n, label, 1, [&](std::size_t q) { return owner[q] == k; });
    for (std::size_t c = 0; c < owner.size(); ++c)
        if (owner[c] == k && label[c] != 1) return false;
    return true;
}

// A 2 x 2 block with material on one diagonal and air on the other, around cell c.
bool checkerboard_at(const std::vector<std::int32_t>& owner, int n, std::size_t c) {
    const int x = int(c % n), y = int(c / n);
    const auto solid = [&](int qx, int qy) {
        return qx >= 0 && qy >= 0 && qx < n && qy < n && owner[std::size_t(qy) * n + qx] >= 0;
    };
    for (int by = y - 1; by <= y; ++by)
        for (int bx = x - 1; bx <= x; ++bx) {
            const bool a = solid(bx, by), b = solid(bx + 1, by), d = solid(bx, by + 1), e = solid(bx + 1, by + 1);
            if (a == e && b == d && a != b) return true;
        }
    return false;
}

}  // namespace

std::size_t open_air_passages(std::vector<std::vector<std::int32_t>>& owner, int n, const Rect& root,
                              const std::vector<Contour>& contours, const std::vector<std::int32_t>& component,
                              const JoinedContours& joined) {
    const std::size_t planes = owner.size();
    const glm::dvec2 cell = (root.max - root.min) / double(n);
    const auto centre = [&](std::size_t c) {
        return root.min + glm::dvec2(double(c % n) + 0.5, double(c / n) + 0.5) * cell;
    };
    std::vector<std::vector<std::size_t>> on_plane(planes);
    for (std::size_t c = 0; c < contours.size(); ++c) on_plane[contours[c].plane].push_back(c);
    const auto is_hole = [&](std::size_t c) {
        if (contours[c].closed.size() < 3) return false;
        std::size_t around = 0;
        for (std::size_t o : on_plane[contours[c].plane])
            if (o != c && contours[o].closed.size() >= 3 &&
                point_in_loops({contours[o].closed}, contours[c].closed.front()))
                ++around;
        return around % 2 == 1;
    };
    std::vector<std::vector<std::int32_t>> air(planes);
    for (std::size_t p = 0; p < planes; ++p) air[p] = air_labels(owner[p], n);

    std::size_t opened = 0;
    for (std::size_t h = 0; h < contours.size(); ++h) {
        if (!is_hole(h) || component[h] < 0) continue;
        const std::size_t p = contours[h].plane;
        // The hole's air: the air components of its layer with a cell centre inside it.
        std::vector<std::int32_t> source;
        for (std::size_t c = 0; c < owner[p].size(); ++c)
            if (air[p][c] > kOutside && point_in_loops({contours[h].closed}, centre(c))) source.push_back(air[p][c]);
        if (source.empty()) {  // a hole narrower than a cell: the enclosed air over its bounding box
            glm::dvec2 lo(1e300), hi(-1e300);
            for (const auto& q : contours[h].closed) lo = glm::min(lo, q), hi = glm::max(hi, q);
            for (std::size_t c = 0; c < owner[p].size(); ++c) {
                const glm::dvec2 m = centre(c);
                if (air[p][c] > kOutside && std::abs(m.x - 0.5 * (lo.x + hi.x)) < 0.5 * (hi.x - lo.x + cell.x) &&
                    std::abs(m.y - 0.5 * (lo.y + hi.y)) < 0.5 * (hi.y - lo.y + cell.y))
                    source.push_back(air[p][c]);
            }
        }
        std::sort(source.begin(), source.end());
        source.erase(std::unique(source.begin(), source.end()), source.end());
        if (source.empty()) continue;  // the hole's air is open already
        // The contours of the neighbouring planes the mesh joins the hole to, below and above.
        std::vector<std::pair<std::size_t, std::size_t>> partners;  // (plane, contour)
        if (p >= 1)
            for (const auto& [lower, upper] : joined[p])
                if (std::size_t(upper) == h) partners.push_back({p - 1, std::size_t(lower)});
        if (p + 1 < planes && p + 1 < joined.size())
            for (const auto& [lower, upper] : joined[p + 1])
                if (std::size_t(lower) == h) partners.push_back({p + 1, std::size_t(upper)});
        for (const auto& [q, u] : partners) {
            if (component[u] < 0) continue;
            // The air beside u in layer q: cells next to u's component on u's air side.
            const bool u_hole = is_hole(u);
            std::vector<std::uint8_t> target_label(std::size_t(n) * n + 1, 0);
            bool any_target = false;
            for (std::size_t c = 0; c < owner[q].size(); ++c) {
                if (air[q][c] < 0) continue;
                bool beside = false;
                for_each_neighbour(c, n, [&](std::size_t e) { beside = beside || owner[q][e] == component[u]; });
                if (beside && point_in_loops({contours[u].closed}, centre(c)) == u_hole)
                    target_label[std::size_t(air[q][c])] = 1, any_target = true;
            }
            if (!any_target) continue;
            const auto in_source = [&](std::int32_t l) { return std::binary_search(source.begin(), source.end(), l); };
            // Joined already: some cell is the hole's air in layer p and the target's in layer q.
            bool joined_now = false;
            for (std::size_t c = 0; c < owner[p].size() && !joined_now; ++c)
                joined_now = air[p][c] >= 0 && in_source(air[p][c]) && air[q][c] >= 0 && target_label[air[q][c]];
            if (joined_now) continue;
            // 0-1 breadth-first search in layer q from the cells over the hole's air to the target
            // air, opening material of one component only; a cell opened must not lie against other
            // air of layer p, nor under or over enclosed air of the layer beyond q.
            const std::size_t beyond = q > p ? q + 1 : (q >= 1 ? q - 1 : planes);
            const auto may_open = [&](std::size_t c, std::int32_t k) {
                if (owner[q][c] != k) return false;
                if (air[p][c] >= 0 && !in_source(air[p][c]) && air[p][c] != kOutside) return false;
                if (beyond < planes && air[beyond][c] > kOutside) return false;
                return true;
            };
            const std::size_t cells = owner[q].size();
            std::vector<std::uint32_t> dist(cells, std::numeric_limits<std::uint32_t>::max());
            std::vector<std::int64_t> from(cells, -1);
            std::vector<std::int32_t> through(cells, -1);  // the component a path opens
            std::deque<std::size_t> queue;
            for (std::size_t c = 0; c < cells; ++c)
                if (air[p][c] >= 0 && in_source(air[p][c]) && owner[q][c] >= 0 && may_open(c, owner[q][c]))
                    dist[c] = 1, through[c] = owner[q][c], queue.push_back(c);
            std::int64_t reached = -1;
            while (!queue.empty()) {
                const std::size_t c = queue.front();
                queue.pop_front();
                if (air[q][c] >= 0 && target_label[air[q][c]]) {
                    reached = std::int64_t(c);
                    break;
                }
                for_each_neighbour(c, n, [&](std::size_t e) {
                    std::uint32_t w;
                    if (air[q][e] >= 0) {
                        if (!target_label[air[q][e]]) return;  // other air of layer q
                        w = 0;
                    } else {
                        const std::int32_t k = through[c] >= 0 ? through[c] : owner[q][e];
                        if (!may_open(e, k)) return;
                        w = 1;
                    }
                    if (dist[c] + w < dist[e]) {
                        dist[e] = dist[c] + w, from[e] = std::int64_t(c);
                        through[e] = w ? owner[q][e] : through[c];
                        w ? queue.push_back(e) : queue.push_front(e);
                    }
                });
            }
            if (reached < 0) continue;
            std::vector<std::size_t> path;
            for (std::int64_t c = reached; c >= 0; c = from[std::size_t(c)])
                if (owner[q][std::size_t(c)] >= 0) path.push_back(std::size_t(c));
            if (path.empty()) continue;
            const std::int32_t k = owner[q][path.front()];
            for (std::size_t c : path) owner[q][c] = -1;
            bool ok = connected(owner[q], n, k);
            for (std::size_t c : path) ok = ok && !checkerboard_at(owner[q], n, c);
            if (!ok) {
                for (std::size_t c : path) owner[q][c] = k;
                continue;
            }
            opened += path.size();
            air[q] = air_labels(owner[q], n);
        }
    }
    return opened;
}

}  // namespace gimg::passes::polycube

// The square's boundary for a cut surface, placed so that both sides of every cut path are sampled
// at the same points, and the joining of those samples in the image (parameterize.h).
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/geometry/topology.h"
#include "gimg/geometry/weld.h"
#include "gimg/passes/parameterize.h"
#include "parameterize/boundary_turning.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace gimg::passes {

namespace {

constexpr std::size_t kNone = std::size_t(-1);

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) { return std::uint64_t(a) << 32 | b; }

// The point of the square's perimeter at `step` of 4 (size - 1), counter-clockwise from (0, 0).
glm::dvec2 perimeter_point(double step, std::uint32_t size) {
    static const glm::dvec2 kSquare[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const double side = double(size - 1), at = step / side;
    const int c = std::min(3, int(std::floor(at)));
    return kSquare[c] + (at - c) * (kSquare[(c + 1) % 4] - kSquare[c]);
}

// Whole steps per segment: at least `least` each, the rest by length, both sides of a path alike.
std::optional<std::vector<std::size_t>> allocate_steps(const std::vector<double>& length,
                                                       const std::vector<std::size_t>& mate,
                                                       const std::vector<std::size_t>& least, std::size_t total) {
    const std::size_t m = length.size();
    const double sum = std::accumulate(length.begin(), length.end(), 0.0);
    std::vector<std::size_t> steps(m);
    std::vector<double> remainder(m);
    std::size_t used = 0;
    for (std::size_t g = 0; g < m; ++g) {
        // A path's second side takes its first side's figures, not its own sum's rounding.
        const std::size_t from = mate[g] != kNone && mate[g] < g ? mate[g] : g;
        const double ideal = sum > 0.0 ? double(total) * length[from] / sum : double(total) / double(m);
        steps[g] = std::max(least[from], std::size_t(std::floor(ideal)));
        remainder[g] = ideal - double(steps[g]);
        used += steps[g];
    }
    std::vector<std::size_t> order;  // one entry per path (its first side) or rim segment
    for (std::size_t g = 0; g < m; ++g)
        if (mate[g] == kNone || g < mate[g]) order.push_back(g);
    // Short segments rounded up to one step can overspend: take steps back where most was given.
    while (used > total) {
        std::size_t most = kNone;
        for (std::size_t g : order) {
            const std::size_t cost = mate[g] == kNone ? 1 : 2;
            if (steps[g] > least[g] && cost <= used - total + 1 && (most == kNone || remainder[g] < remainder[most]))
                most = g;
        }
        if (most == kNone) return std::nullopt;
        --steps[most];
        remainder[most] += 1.0;
        if (mate[most] != kNone) --steps[mate[most]];
        used -= mate[most] == kNone ? 1 : 2;
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
    for (std::size_t left = total - used; left > 0;) {
        bool added = false;
        for (std::size_t g : order) {
            const std::size_t cost = mate[g] == kNone ? 1 : 2;
            if (cost > left) continue;
            ++steps[g];
            if (mate[g] != kNone) ++steps[mate[g]];
            left -= cost;
            added = true;
            if (left == 0) break;
        }
        if (!added) return std::nullopt;
    }
    return steps;
}

}  // namespace

glm::uvec2 border_pixel(std::uint32_t step, std::uint32_t size) {
    const std::uint32_t side = size - 1, c = step / side, t = step % side;
    switch (c) {
        case 0:
            return {t, side};
        case 1:
            return {side, side - t};
        case 2:
            return {side - t, 0};
        default:
            return {0, t};
    }
}

std::optional<SeamBoundary> seam_boundary(DiskCut& cut, std::uint32_t size) {
    if (size < 4) return std::nullopt;  // joined, a 2 x 2 or 3 x 3 image keeps no face
    geo::Mesh& disk = cut.disk;
    std::vector<std::uint32_t> loop = square_boundary(disk, geo::build_adjacency(disk)).loop;
    const std::size_t n = loop.size();
    auto source = [&](std::size_t i) { return cut.source[loop[i % n]]; };
    // A boundary of fewer than 4 vertices, given more (geo::split_short_boundary), has no seam to place.
    for (std::size_t i = 0; i < n; ++i)
        if (source(i) == geo::kInvalidIndex) return std::nullopt;
    // Nodes: where a path ends, paths meet, or a path meets a hole.
    std::size_t first = kNone;
    for (std::size_t i = 0; i < n && first == kNone; ++i)
        if (cut.cut_degree[source(i)] != 2) first = i;
    if (first == kNone) return std::nullopt;
    std::rotate(loop.begin(), loop.begin() + std::ptrdiff_t(first), loop.end());
    std::vector<std::size_t> nodes;
    for (std::size_t i = 0; i < n; ++i)
        if (cut.cut_degree[source(i)] != 2) nodes.push_back(i);
    const std::size_t m = nodes.size();
    nodes.push_back(n);
    // Each loop edge's mate runs back over the same input edge on the path's other side.
    std::unordered_map<std::uint64_t, std::size_t> edge_at;
    for (std::size_t i = 0; i < n; ++i) edge_at[edge_key(source(i), source(i + 1))] = i;
    auto segment_of = [&](std::size_t edge) {
        return std::size_t(std::upper_bound(nodes.begin(), nodes.end(), edge) - nodes.begin()) - 1;
    };
    std::vector<std::size_t> mate(m, kNone);
    std::vector<double> length(m, 0.0);
    std::vector<double> chord(n + 1, 0.0);  // from the segment's node to each loop position
    for (std::size_t g = 0; g < m; ++g) {
        const auto back = edge_at.find(edge_key(source(nodes[g] + 1), source(nodes[g])));
        if (back != edge_at.end()) {
            const std::size_t h = segment_of(back->second);
            // The mate must end where this one starts and be as long in edges.
            if (nodes[h + 1] != back->second + 1 || nodes[h + 1] - nodes[h] != nodes[g + 1] - nodes[g])
                return std::nullopt;
            mate[g] = h;
        }
        for (std::size_t i = nodes[g]; i < nodes[g + 1]; ++i) {
            chord[i] = length[g];
            length[g] += glm::distance(disk.positions[loop[i]], disk.positions[loop[(i + 1) % n]]);
        }
    }
    // A loop from a node back to itself (a hole's rim, a handle as small as a few edges) keeps at
    // least 5 steps and each of two paths between the same two nodes 3: with fewer, joined, the loop
    // is a point or one edge twice, or a corner of the square inside it lets one pixel touch both of
    // its ends (the corner's triangles close it), and the reconstruction pinches there: femur kept
    // one vertex of two fans, small holes of pig and chinese_dragon_10k closed, a torus of 4 x 3
    // vertices lost its handle. Where the perimeter is too short for that, the seam stays open.
    std::vector<std::size_t> least(m, 1);
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> paths_between;
    auto ends = [&](std::size_t g) {
        const std::uint32_t a = source(nodes[g]), b = source(nodes[g + 1]);
        return std::pair<std::uint32_t, std::uint32_t>(std::min(a, b), std::max(a, b));
    };
    for (std::size_t g = 0; g < m; ++g)
        if (mate[g] == kNone || g < mate[g]) ++paths_between[ends(g)];
    for (std::size_t g = 0; g < m; ++g) {
        const auto [a, b] = ends(g);
        least[g] = a == b ? 5 : paths_between[{a, b}] > 1 ? 3 : 1;
    }
    const std::size_t total = 4 * std::size_t(size - 1);
    const auto steps = allocate_steps(length, mate, least, total);
    if (!steps) return std::nullopt;
    std::vector<std::size_t> start(m + 1, 0);
    for (std::size_t g = 0; g < m; ++g) start[g + 1] = start[g] + (*steps)[g];

    // Each loop vertex's step: its node's, and between nodes by chord length.
    std::vector<double> step(n);
    for (std::size_t g = 0; g < m; ++g)
        for (std::size_t i = nodes[g]; i < nodes[g + 1]; ++i)
            step[i] = double(start[g]) +
                      double((*steps)[g]) * (length[g] > 0.0 ? chord[i] / length[g]
                                                             : double(i - nodes[g]) / double(nodes[g + 1] - nodes[g]));

    // The mate of each whole step, with node 0 at step 0.
    std::vector<std::uint32_t> mate_step(total);
    for (std::size_t g = 0; g < m; ++g)
        for (std::size_t s = start[g]; s < start[g + 1]; ++s)
            mate_step[s] = std::uint32_t(mate[g] == kNone ? s : (start[mate[g] + 1] - (s - start[g])) % total);

    // The square's corners: of every whole-step turn of the perimeter, the one whose four corners fall
    // nearest where the boundary turns most, as a disk's corners are chosen (bunny at 194: 80.2 dB,
    // 72.9 with corner 0 on a node).
    const std::vector<double> turn = detail::boundary_turning(disk, loop);
    auto nearest = [&](double at) {
        const std::size_t i = std::size_t(std::lower_bound(step.begin(), step.end(), at) - step.begin());
        const std::size_t before = i == 0 ? n - 1 : i - 1, after = i % n;
        const double to_before = i == 0 ? at + double(total) - step[before] : at - step[before];
        const double to_after = i < n ? step[i] - at : step[0] + double(total) - at;
        return to_after <= to_before ? after : before;
    };
    std::size_t shift = 0;
    double most = -1.0;
    for (std::size_t sigma = 0; sigma < total; ++sigma) {
        double turned = 0.0;
        for (std::size_t c = 0; c < 4; ++c) turned += turn[nearest(double((sigma + c * (size - 1)) % total))];
        if (turned > most + 1e-9) most = turned, shift = sigma;
    }
    // Steps counted from there: the loop turned to start at the first vertex at or after it.
    const std::size_t first_after =
        std::size_t(std::lower_bound(step.begin(), step.end(), double(shift)) - step.begin());
    std::rotate(loop.begin(), loop.begin() + std::ptrdiff_t(first_after), loop.end());
    std::rotate(step.begin(), step.begin() + std::ptrdiff_t(first_after), step.end());
    for (double& x : step) x = x >= double(shift) ? x - double(shift) : x + double(total - shift);

    // A corner inside a boundary edge gets a vertex there, its face split in two; corner 0 comes last,
    // at the loop's end (step total), and is then turned to the front.
    std::unordered_map<std::uint64_t, std::uint32_t> face_of;  // boundary edge (a, b) in loop order
    for (std::uint32_t f = 0; f < disk.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) face_of[edge_key(disk.triangles[f][k], disk.triangles[f][(k + 1) % 3])] = f;
    std::array<std::uint32_t, 4> corners{};
    for (int c : {1, 2, 3, 4}) {
        const double at = double(c) * double(size - 1);
        const std::size_t size_now = loop.size();
        const std::size_t i = std::size_t(std::lower_bound(step.begin(), step.end(), at) - step.begin());
        const double next = i < size_now ? step[i] : step[0] + double(total);  // step[i] >= at, or past the end
        // On a vertex, or so near one that a new one would make a face of no area: that vertex.
        if (next - at < 1e-6) {
            if (i < size_now) step[i] = at;
            corners[c % 4] = loop[i % size_now];
            continue;
        }
        // Before it: the vertex before, or (a first edge longer than a side) the loop's last one.
        const std::size_t before = i > 0 ? i - 1 : size_now - 1;
        const double previous = i > 0 ? step[before] : step[before] - double(total);
        if (at - previous < 1e-6) {
            step[before] = i > 0 ? at : at + double(total);
            corners[c % 4] = loop[before];
            continue;
        }
        const std::uint32_t a = loop[before], b = loop[i % size_now];
        const double t = (at - previous) / (next - previous);
        const auto w = std::uint32_t(disk.positions.size());
        disk.positions.push_back(glm::mix(disk.positions[a], disk.positions[b], t));
        if (disk.normals.size() + 1 == disk.positions.size())
            disk.normals.push_back(glm::normalize(glm::mix(disk.normals[a], disk.normals[b], t)));
        if (disk.texcoords.size() + 1 == disk.positions.size())
            disk.texcoords.push_back(glm::mix(disk.texcoords[a], disk.texcoords[b], t));
        cut.source.push_back(geo::kInvalidIndex);
        const std::uint32_t f = face_of.at(edge_key(a, b));
        glm::uvec3& tri = disk.triangles[f];
        const int k = tri[0] == a ? 0 : tri[1] == a ? 1 : 2;
        const std::uint32_t x = tri[(k + 2) % 3];
        tri = {a, w, x};
        disk.triangles.push_back({w, b, x});
        face_of[edge_key(a, w)] = f;
        face_of[edge_key(w, b)] = std::uint32_t(disk.triangles.size() - 1);
        loop.insert(loop.begin() + std::ptrdiff_t(i), w);
        step.insert(step.begin() + std::ptrdiff_t(i), at);
        corners[c % 4] = w;
    }
    const std::size_t zero = std::size_t(std::find(loop.begin(), loop.end(), corners[0]) - loop.begin());
    std::rotate(loop.begin(), loop.begin() + std::ptrdiff_t(zero), loop.end());
    std::rotate(step.begin(), step.begin() + std::ptrdiff_t(zero), step.end());
    step[0] = 0.0;  // it stood at the end, step `total`, or at 0 already

    SeamBoundary out;
    out.boundary.loop = loop;
    out.boundary.corners = corners;
    out.boundary.uv.resize(loop.size());
    for (std::size_t i = 0; i < loop.size(); ++i) out.boundary.uv[i] = perimeter_point(step[i], size);
    for (int c = 0; c < 4; ++c)  // exactly on the corner, not a rounding away
        out.boundary.uv[std::size_t(std::find(loop.begin(), loop.end(), corners[c]) - loop.begin())] =
            perimeter_point(double(c) * double(size - 1), size);
    out.mate.resize(total);
    for (std::size_t s = 0; s < total; ++s)
        out.mate[s] = std::uint32_t((mate_step[(s + shift) % total] + total - shift) % total);
    return out;
}

std::size_t join_seam(PositionImage& image, const std::vector<std::uint32_t>& mate) {
    const std::uint32_t size = image.width;
    if (image.height != size || mate.size() != 4 * std::size_t(size - 1))
        throw geo::InputError("join_seam: the mate table is not the image's border");
    std::vector<std::uint32_t> parent(mate.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](std::uint32_t s) {
        while (parent[s] != s) s = parent[s] = parent[parent[s]];
        return s;
    };
    for (std::uint32_t s = 0; s < mate.size(); ++s) parent[root(s)] = root(mate[s]);
    std::vector<glm::dvec3> sum(mate.size(), glm::dvec3(0.0));
    std::vector<std::uint32_t> count(mate.size(), 0);
    auto pixel = [&](std::uint32_t s) {
        const glm::uvec2 p = border_pixel(s, size);
        return image.index(p.x, p.y);
    };
    for (std::uint32_t s = 0; s < mate.size(); ++s) {
        const std::size_t i = pixel(s);
        sum[root(s)] += glm::dvec3(image.xyz[3 * i], image.xyz[3 * i + 1], image.xyz[3 * i + 2]);
        ++count[root(s)];
    }
    std::size_t changed = 0;
    for (std::uint32_t s = 0; s < mate.size(); ++s) {
        const std::uint32_t r = root(s);
        if (count[r] < 2) continue;
        const glm::vec3 mean(sum[r] / double(count[r]));
        const std::size_t i = pixel(s);
        for (int k = 0; k < 3; ++k) image.xyz[3 * i + std::size_t(k)] = mean[k];
        ++changed;
    }
    return changed;
}

std::size_t close_seam(geo::Mesh& reconstruction) {
    geo::Mesh& m = reconstruction;
    const std::size_t before = m.vertex_count();
    geo::weld_identical_vertices(m);
    std::erase_if(m.triangles, [](const glm::uvec3& t) { return t.x == t.y || t.y == t.z || t.z == t.x; });
    // Where both sides of a path turn a corner of the square, each corner pixel's quad gives a
    // triangle of three border pixels, and joined they are one triangle twice, facing both ways, on
    // an edge of four faces: the pair goes.
    std::map<std::array<std::uint32_t, 3>, std::vector<std::size_t>> by_corners;  // sorted corners -> faces
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
        std::array<std::uint32_t, 3> key{m.triangles[f].x, m.triangles[f].y, m.triangles[f].z};
        std::sort(key.begin(), key.end());
        by_corners[key].push_back(f);
    }
    std::vector<std::uint8_t> drop(m.triangles.size(), 0);
    for (const auto& [corners, faces] : by_corners)
        for (std::size_t i = 0; i + 1 < faces.size(); i += 2) drop[faces[i]] = drop[faces[i + 1]] = 1;
    std::vector<glm::uvec3> kept;
    for (std::size_t f = 0; f < m.triangles.size(); ++f)
        if (!drop[f]) kept.push_back(m.triangles[f]);
    m.triangles = std::move(kept);
    // Vertices left in no face (such a corner pixel) go.
    std::vector<std::uint8_t> used(m.vertex_count(), 0);
    for (const glm::uvec3& t : m.triangles) used[t.x] = used[t.y] = used[t.z] = 1;
    std::vector<std::uint32_t> index(m.vertex_count(), geo::kInvalidIndex);
    std::uint32_t next = 0;
    for (std::size_t v = 0; v < used.size(); ++v)
        if (used[v]) {
            index[v] = next;
            m.positions[next++] = m.positions[v];
        }
    m.positions.resize(next);
    for (glm::uvec3& t : m.triangles) t = {index[t.x], index[t.y], index[t.z]};
    m.texcoords.clear();
    m.normals = geo::vertex_normals(m);
    return before - m.vertex_count();
}

SeamJoin rebuild_over_seam(PositionImage& image, const std::optional<SeamBoundary>& seam,
                           const std::function<geo::Mesh(const PositionImage&)>& rebuild) {
    SeamJoin out;
    if (!seam) {
        out.mesh = rebuild(image);
        return out;
    }
    PositionImage joined = image;
    out.joined_pixels = join_seam(joined, seam->mate);
    out.mesh = rebuild(joined);
    out.merged_vertices = close_seam(out.mesh);
    const geo::MeshInfo info = geo::analyze_topology(out.mesh);
    if (info.components == 1 && info.non_manifold_edges == 0 && info.non_manifold_vertices == 0 &&
        info.inconsistent_edges == 0) {
        image = std::move(joined);
        out.joined = true;
        return out;
    }
    out.mesh = rebuild(image);
    out.joined_pixels = out.merged_vertices = 0;
    return out;
}

}  // namespace gimg::passes

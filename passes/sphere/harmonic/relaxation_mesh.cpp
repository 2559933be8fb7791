// Level layout (fans, cotangent weights, colouring) and the CPU reference of the relaxation.
#include "sphere/harmonic/relaxation_mesh.h"

#include "sphere/sphere_steps.h"

#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace gimg::passes::detail {

RelaxationMesh build_relaxation_mesh(const geo::Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    RelaxationMesh level;
    // Per vertex, the corners it owns: for triangle (i, a, b) the fan step a -> b.
    std::vector<std::uint32_t> corner_offsets(n + 1, 0);
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++corner_offsets[t[k] + 1];
    for (std::size_t i = 0; i < n; ++i) corner_offsets[i + 1] += corner_offsets[i];
    // Half the cotangent of each triangle's angle at corner j, once per angle (each serves two
    // spokes), in chunks of triangles on the CPU's threads.
    std::vector<double> half_cot(3 * mesh.face_count());
    geo::parallel_for_chunks(mesh.face_count(), kLevelChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t f = begin; f < end; ++f) {
            const glm::uvec3 t = mesh.triangles[f];
            const glm::dvec3 p[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
            for (int j = 0; j < 3; ++j)
                half_cot[3 * f + j] = 0.5 * geo::clamped_cotangent(p[(j + 1) % 3] - p[j], p[(j + 2) % 3] - p[j]);
        }
    });
    // Each vertex's corners (3 f + k: corner k of triangle f), in the triangles' order.
    std::vector<std::uint32_t> corners(corner_offsets.back());
    {
        std::vector<std::uint32_t> fill(corner_offsets.begin(), corner_offsets.end() - 1);
        for (std::size_t f = 0; f < mesh.face_count(); ++f)
            for (int k = 0; k < 3; ++k) corners[fill[mesh.triangles[f][k]]++] = std::uint32_t(3 * f + std::size_t(k));
    }
    level.ring_offsets.assign(corner_offsets.begin(), corner_offsets.end());
    level.ring.resize(corner_offsets.back());
    level.ring_weights.assign(corner_offsets.back(), 0.0);
    // The fans, in chunks of vertices on the CPU's threads (each writes only its vertices' spokes);
    // a broken fan's message names the lowest such vertex, as one thread would.
    std::vector<std::string> broken(geo::chunk_count(n, kLevelChunk));
    geo::parallel_for_chunks(n, kLevelChunk, [&](std::size_t chunk, std::size_t first, std::size_t last) {
        std::vector<std::uint32_t> from;  // per corner of the vertex: the spoke its triangle starts at
        for (std::size_t i = first; i < last; ++i) {
            const std::uint32_t begin = corner_offsets[i], end = corner_offsets[i + 1], degree = end - begin;
            if (degree == 0) {
                broken[chunk] = "vertex " + std::to_string(i) + " is in no triangle";
                return;
            }
            from.resize(degree);
            for (std::uint32_t c = 0; c < degree; ++c) {
                const std::uint32_t corner = corners[begin + c];
                from[c] = mesh.triangles[corner / 3][(corner % 3 + 1) % 3];
            }
            // Walk the fan: after the spoke to `from`, the next spoke is that corner's `to`.
            std::uint32_t c = 0;
            for (std::uint32_t k = 0; k < degree; ++k) {
                const std::uint32_t corner = corners[begin + c], f = corner / 3, j = corner % 3;
                const std::uint32_t a = (j + 1) % 3, b = (j + 2) % 3;
                level.ring[begin + k] = from[c];
                const std::uint32_t to = mesh.triangles[f][b];
                const std::uint32_t next_k = (k + 1) % degree;
                // Spoke (j, a) is opposite corner b; spoke (j, b) is opposite corner a.
                level.ring_weights[begin + k] += half_cot[3 * f + b];
                level.ring_weights[begin + next_k] += half_cot[3 * f + a];
                const auto found = std::uint32_t(std::find(from.begin(), from.end(), to) - from.begin());
                if (found == degree && next_k != 0) {
                    broken[chunk] = "the triangles around vertex " + std::to_string(i) + " do not form one closed fan";
                    return;
                }
                c = found;
                if (c == 0 && next_k != 0) {  // a second fan: a non-manifold vertex
                    broken[chunk] = "the triangles around vertex " + std::to_string(i) + " form more than one fan";
                    return;
                }
            }
            if (c != 0) {
                broken[chunk] = "the triangles around vertex " + std::to_string(i) + " do not form one closed fan";
                return;
            }
        }
    });
    for (const std::string& why : broken)
        if (!why.empty()) throw geo::InputError(why);
    // Greedy colouring in smallest-last order: repeatedly take away a vertex of least remaining
    // degree, then colour in reverse. A planar graph always has a vertex of degree <= 5, so a
    // genus-0 mesh needs at most 6 colours (6 dispatches per sweep).
    std::vector<std::uint32_t> order;
    order.reserve(n);
    {
        std::vector<std::uint32_t> degree(n);
        std::vector<std::vector<std::uint32_t>> buckets;
        for (std::uint32_t v = 0; v < n; ++v) {
            degree[v] = level.ring_offsets[v + 1] - level.ring_offsets[v];
            if (degree[v] >= buckets.size()) buckets.resize(degree[v] + 1);
            buckets[degree[v]].push_back(v);
        }
        std::vector<std::uint8_t> removed(n, 0);
        std::size_t lowest = 0;
        while (order.size() < n) {
            lowest = lowest > 0 ? lowest - 1 : 0;  // a removal lowers degrees by at most one
            while (buckets[lowest].empty()) ++lowest;
            const std::uint32_t v = buckets[lowest].back();
            buckets[lowest].pop_back();
            if (removed[v] || degree[v] != lowest) continue;  // a stale entry
            removed[v] = 1;
            order.push_back(v);
            for (std::uint32_t k = level.ring_offsets[v]; k < level.ring_offsets[v + 1]; ++k) {
                const std::uint32_t u = level.ring[k];
                if (!removed[u]) buckets[--degree[u]].push_back(u);
            }
        }
        std::reverse(order.begin(), order.end());
    }
    constexpr std::uint32_t kNone = ~0u;
    std::vector<std::uint32_t> colour(n, kNone);
    std::uint32_t colours = 0;
    std::vector<std::uint8_t> used;
    for (std::uint32_t v : order) {
        used.assign(colours + 1, 0);
        for (std::uint32_t k = level.ring_offsets[v]; k < level.ring_offsets[v + 1]; ++k)
            if (colour[level.ring[k]] != kNone) used[colour[level.ring[k]]] = 1;
        std::uint32_t c = 0;
        while (used[c]) ++c;
        colour[v] = c;
        colours = std::max(colours, c + 1);
    }
    level.colour_offsets.assign(colours + 1, 0);
    for (std::uint32_t c : colour) ++level.colour_offsets[c + 1];
    for (std::uint32_t c = 0; c < colours; ++c) level.colour_offsets[c + 1] += level.colour_offsets[c];
    level.colour_members.resize(n);
    std::vector<std::uint32_t> cursor(level.colour_offsets.begin(), level.colour_offsets.end() - 1);
    for (std::uint32_t v = 0; v < n; ++v) level.colour_members[cursor[colour[v]]++] = v;
    return level;
}

namespace {

// How well triangle (at, a, b) is oriented: 2 passes the relaxation test, 1 only the kernel
// test, 0 neither (flipped, degenerate, or within the rounding margin).
int orientation_grade(const glm::dvec3& at, const glm::dvec3& a, const glm::dvec3& b) {
    if (counter_clockwise(at, a, b, kRelaxMargin)) return 2;
    return counter_clockwise(at, a, b, kKernelMargin) ? 1 : 0;
}

// True when moving v from `from` to `to` lowers the grade of no triangle of its fan, and turns
// no triangle of grade 0 further clockwise. Judged per triangle: counts would let a sliver that
// passes become a flip while another triangle mends. Within the margin the sign of det is rounding
// noise, which the next vertex's move took for a flip it could deepen (measured: a tetrahedron's
// face went from det 4e-16 to -9e-10 in two moves), so there det may only grow.
bool keeps_every_grade(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t v,
                       const glm::dvec3& from, const glm::dvec3& to) {
    const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
    for (std::uint32_t k = 0; k < degree; ++k) {
        const glm::dvec3& a = y[level.ring[begin + k]];
        const glm::dvec3& b = y[level.ring[begin + (k + 1) % degree]];
        const int after = orientation_grade(to, a, b);
        if (after == 2) continue;
        const int before = orientation_grade(from, a, b);
        if (after < before) return false;
        if (after == 0 && before == 0 && orientation(to, a, b) < orientation(from, a, b)) return false;
    }
    return true;
}

}  // namespace

glm::dvec3 relaxed_position(const RelaxationMesh& level, const std::vector<glm::dvec3>& y, std::uint32_t v,
                            bool uniform_weights) {
    glm::dvec3 sum(0.0);
    for (std::uint32_t k = level.ring_offsets[v]; k < level.ring_offsets[v + 1]; ++k)
        sum += (uniform_weights ? 1.0 : level.ring_weights[k]) * y[level.ring[k]];
    const double length = glm::length(sum);
    const glm::dvec3 current = y[v];
    if (!(length > 1e-300)) return current;
    const glm::dvec3 target = sum / length;
    double t = 1.0;
    for (int attempt = 0; attempt <= kMaxStepHalvings; ++attempt, t *= 0.5) {
        const glm::dvec3 chord = current + t * (target - current);
        const double chord_length = glm::length(chord);
        if (!(chord_length > 1e-12)) continue;
        const glm::dvec3 candidate = chord / chord_length;
        if (keeps_every_grade(level, y, v, current, candidate)) return candidate;
    }
    return current;
}

void relax_sweep_cpu(const RelaxationMesh& level, std::vector<glm::dvec3>& y, bool uniform_weights) {
    for (std::size_t c = 0; c < level.colour_count(); ++c) {
        // Same-colour vertices do not see each other's moves: compute all, then write.
        const std::uint32_t begin = level.colour_offsets[c], end = level.colour_offsets[c + 1];
        std::vector<glm::dvec3> moved(end - begin);
        for (std::uint32_t m = begin; m < end; ++m)
            moved[m - begin] = relaxed_position(level, y, level.colour_members[m], uniform_weights);
        for (std::uint32_t m = begin; m < end; ++m) y[level.colour_members[m]] = moved[m - begin];
    }
}

MapStats map_stats_cpu(const RelaxationMesh& level, const std::vector<glm::dvec3>& y) {
    // Chunks of vertices on the CPU's threads, their sums added in chunk order: the same result on
    // any number of threads (armadillo_loop1: 3.3 -> 1.7 ms on two).
    const std::size_t n = level.vertex_count();
    std::vector<MapStats> parts(geo::chunk_count(n, kLevelChunk));
    geo::parallel_for_chunks(n, kLevelChunk, [&](std::size_t chunk, std::size_t first, std::size_t end) {
        MapStats& part = parts[chunk];
        for (auto v = std::uint32_t(first); v < end; ++v) {
            const std::uint32_t begin = level.ring_offsets[v], degree = level.ring_offsets[v + 1] - begin;
            for (std::uint32_t k = 0; k < degree; ++k) {
                const std::uint32_t a = level.ring[begin + k], b = level.ring[begin + (k + 1) % degree];
                const glm::dvec3 d = y[v] - y[a];
                part.energy += 0.5 * level.ring_weights[begin + k] * glm::dot(d, d);
                if (v < a && v < b) {
                    part.kernel_failures += !counter_clockwise(y[v], y[a], y[b]);
                    part.flips += !(orientation(y[v], y[a], y[b]) > 0.0);
                }
            }
            part.centroid += y[v];
        }
    });
    MapStats stats;
    for (const MapStats& part : parts) {
        stats.energy += part.energy;
        stats.kernel_failures += part.kernel_failures;
        stats.flips += part.flips;
        stats.centroid += part.centroid;
    }
    stats.centroid /= double(n);
    return stats;
}

}  // namespace gimg::passes::detail

#include "gimg/geometry/adjacency.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace gimg::geo {

namespace {

// Exclusive prefix sum in place: counts[i] becomes the start of bucket i; returns the total.
std::uint32_t exclusive_scan(std::vector<std::uint32_t>& counts) {
    std::uint64_t sum = 0;
    for (auto& c : counts) {
        const std::uint64_t n = c;
        c = static_cast<std::uint32_t>(sum);
        sum += n;
    }
    if (sum > 0xffffffffull) throw std::length_error("mesh too large for 32-bit adjacency indices");
    return static_cast<std::uint32_t>(sum);
}

void check_indices(const Mesh& mesh) {
    const std::size_t v = mesh.vertex_count();
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        if (t.x >= v || t.y >= v || t.z >= v)
            throw std::invalid_argument("triangle " + std::to_string(f) +
                                        " names a vertex index past the vertex count " + std::to_string(v));
    }
}

void build_vertex_faces(const Mesh& mesh, MeshAdjacency& adj) {
    const std::size_t vcount = mesh.vertex_count();
    std::vector<std::uint32_t> start(vcount + 1, 0);
    for (const glm::uvec3& t : mesh.triangles) {
        start[t.x]++;
        if (t.y != t.x) start[t.y]++;
        if (t.z != t.x && t.z != t.y) start[t.z]++;
    }
    const std::uint32_t total = exclusive_scan(start);
    start[vcount] = total;
    adj.vertex_face_offsets = start;
    adj.vertex_faces.resize(total);
    // Faces are visited in increasing order, so every bucket comes out sorted.
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        adj.vertex_faces[start[t.x]++] = f;
        if (t.y != t.x) adj.vertex_faces[start[t.y]++] = f;
        if (t.z != t.x && t.z != t.y) adj.vertex_faces[start[t.z]++] = f;
    }
}

struct HalfEntry {
    std::uint32_t hi;  // larger endpoint (the bucket is the smaller one)
    std::uint32_t face;
    std::uint32_t corner;  // k: the edge joins corners k and (k + 1) % 3
};

void build_edges(const Mesh& mesh, MeshAdjacency& adj) {
    const std::size_t vcount = mesh.vertex_count();
    const std::size_t fcount = mesh.face_count();
    // Bucket every face side by its smaller endpoint; buckets hold a vertex's few sides, so a
    // tiny sort per bucket replaces a global sort of 3F keys.
    std::vector<std::uint32_t> start(vcount + 1, 0);
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if (a != b) start[std::min(a, b)]++;
        }
    const std::uint32_t total = exclusive_scan(start);
    start[vcount] = total;
    std::vector<std::uint32_t> bucket_begin = start;
    std::vector<HalfEntry> entries(total);
    for (std::uint32_t f = 0; f < fcount; ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if (a != b) entries[start[std::min(a, b)]++] = {std::max(a, b), f, k};
        }
    }

    adj.face_edges.assign(3 * fcount, kInvalidIndex);
    adj.edges.clear();
    adj.edges.reserve(total);  // about 2E entries for a closed manifold mesh, 3F = 2E
    adj.edge_faces.clear();
    adj.edge_faces.reserve(total);
    adj.edge_face_offsets.clear();
    adj.edge_face_offsets.reserve(total / 2 + 2);
    for (std::uint32_t lo = 0; lo < vcount; ++lo) {
        const auto first = entries.begin() + bucket_begin[lo];
        const auto last = entries.begin() + bucket_begin[lo + 1];
        std::sort(first, last,
                  [](const HalfEntry& x, const HalfEntry& y) { return x.hi != y.hi ? x.hi < y.hi : x.face < y.face; });
        for (auto it = first; it != last; ++it) {
            const bool new_edge = it == first || it->hi != (it - 1)->hi;
            if (new_edge) {
                adj.edge_face_offsets.push_back(static_cast<std::uint32_t>(adj.edge_faces.size()));
                adj.edges.push_back(lo);
                adj.edges.push_back(it->hi);
            }
            const auto e = static_cast<std::uint32_t>(adj.edges.size() / 2 - 1);
            // A face naming the same edge twice (a, b, a) is listed once.
            if (new_edge || it->face != (it - 1)->face) adj.edge_faces.push_back(it->face);
            adj.face_edges[3 * std::size_t(it->face) + it->corner] = e;
        }
    }
    adj.edge_face_offsets.push_back(static_cast<std::uint32_t>(adj.edge_faces.size()));
}

void build_vertex_vertices(std::size_t vcount, MeshAdjacency& adj) {
    const std::size_t ecount = adj.edge_count();
    std::vector<std::uint32_t> start(vcount + 1, 0);
    for (std::size_t e = 0; e < ecount; ++e) {
        start[adj.edges[2 * e]]++;
        start[adj.edges[2 * e + 1]]++;
    }
    const std::uint32_t total = exclusive_scan(start);
    start[vcount] = total;
    adj.vertex_vertex_offsets = start;
    adj.vertex_vertices.resize(total);
    // Edges are in lexicographic order (lo < hi). Vertex v first receives every lo < v of the
    // edges (lo, v), in increasing lo, then every hi > v of its own edges (v, hi) in increasing hi:
    // each list comes out sorted without a sort.
    for (std::size_t e = 0; e < ecount; ++e) {
        const std::uint32_t a = adj.edges[2 * e], b = adj.edges[2 * e + 1];
        adj.vertex_vertices[start[a]++] = b;
        adj.vertex_vertices[start[b]++] = a;
    }
}

}  // namespace

MeshAdjacency build_adjacency(const Mesh& mesh) {
    check_indices(mesh);
    if (mesh.face_count() > 0xffffffffull / 3) throw std::length_error("mesh too large for 32-bit adjacency indices");
    MeshAdjacency adj;
    build_vertex_faces(mesh, adj);
    build_edges(mesh, adj);
    build_vertex_vertices(mesh.vertex_count(), adj);
    return adj;
}

std::uint32_t MeshAdjacency::find_edge(std::uint32_t a, std::uint32_t b) const {
    if (a == b) return kInvalidIndex;
    const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
    std::size_t first = 0, count = edge_count();
    while (count > 0) {  // lower_bound over the (lo, hi) pairs
        const std::size_t half = count / 2, mid = first + half;
        const std::uint32_t mlo = edges[2 * mid], mhi = edges[2 * mid + 1];
        if (mlo < lo || (mlo == lo && mhi < hi)) {
            first = mid + 1;
            count -= half + 1;
        } else {
            count = half;
        }
    }
    if (first < edge_count() && edges[2 * first] == lo && edges[2 * first + 1] == hi)
        return static_cast<std::uint32_t>(first);
    return kInvalidIndex;
}

std::vector<std::uint8_t> MeshAdjacency::interior_vertices() const {
    const std::size_t vcount = vertex_count();
    std::vector<std::uint8_t> interior(vcount, 0);
    for (std::size_t v = 0; v < vcount; ++v)
        interior[v] = vertex_vertex_offsets[v + 1] > vertex_vertex_offsets[v] ? 1 : 0;
    for (std::size_t e = 0; e < edge_count(); ++e)
        if (edge_face_count(e) != 2) interior[edges[2 * e]] = interior[edges[2 * e + 1]] = 0;
    // With two faces on every edge the faces around v form one or more closed fans; only a single
    // fan is a disk (two cones touching at a vertex are not). Walk the fan from the first face.
    for (std::size_t v = 0; v < vcount; ++v) {
        if (!interior[v]) continue;
        const auto faces = faces_of_vertex(v);
        // The two edges of face f at v. False for a face that repeats a vertex index: such a
        // fan is not a disk.
        auto edges_at_v = [&](std::uint32_t f, std::uint32_t& first, std::uint32_t& second) {
            int found = 0;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t e = face_edges[3 * std::size_t(f) + k];
                if (e == kInvalidIndex) return false;
                if (edges[2 * std::size_t(e)] == v || edges[2 * std::size_t(e) + 1] == v)
                    (found++ == 0 ? first : second) = e;
            }
            return found == 2;
        };
        std::uint32_t f = faces[0], e_out = 0, e_in = 0;
        if (!edges_at_v(f, e_out, e_in)) {
            interior[v] = 0;
            continue;
        }
        std::size_t steps = 0;
        std::uint32_t e = e_out;
        do {
            const auto pair = faces_of_edge(e);
            f = pair[0] == f ? pair[1] : pair[0];
            std::uint32_t a = 0, b = 0;
            if (!edges_at_v(f, a, b)) {
                steps = 0;
                break;
            }
            e = a == e ? b : a;
            ++steps;
        } while (f != faces[0] && steps <= faces.size());
        if (steps != faces.size()) interior[v] = 0;
    }
    return interior;
}

}  // namespace gimg::geo

#include "gimg/geometry/disk_cut.h"

#include <glm/geometric.hpp>

#include <limits>
#include <numeric>
#include <queue>

namespace gimg::geo {

std::vector<std::uint8_t> initial_cut(const Mesh& mesh, const MeshAdjacency& adj) {
    const std::size_t faces = mesh.face_count(), edges = adj.edge_count();
    std::vector<std::uint8_t> cut(edges, 0);
    for (std::size_t e = 0; e < edges; ++e) cut[e] = adj.edge_face_count(e) == 2;
    // A spanning tree of the faces, grown across interior edges: the edges it crosses stay closed.
    std::vector<std::uint8_t> reached(faces, 0);
    std::vector<std::uint32_t> queue;
    for (std::uint32_t seed = 0; seed < faces; ++seed) {
        if (reached[seed]) continue;
        reached[seed] = 1;
        queue.push_back(seed);
        for (std::size_t q = queue.size() - 1; q < queue.size(); ++q) {
            const std::uint32_t f = queue[q];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t e = adj.face_edges[3 * f + k];
                if (e == kInvalidIndex || adj.edge_face_count(e) != 2) continue;
                const auto both = adj.faces_of_edge(e);
                const std::uint32_t other = both[0] == f ? both[1] : both[0];
                if (reached[other]) continue;
                reached[other] = 1;
                cut[e] = 0;
                queue.push_back(other);
            }
        }
    }
    // Prune dangling branches: a cut edge at a vertex with no other cut or boundary edge opens
    // nothing that the rest does not.
    const std::size_t n = adj.vertex_count();
    std::vector<std::uint32_t> cut_degree(n, 0), boundary_degree(n, 0);
    for (std::size_t e = 0; e < edges; ++e)
        for (int s = 0; s < 2; ++s) {
            if (cut[e]) ++cut_degree[adj.edges[2 * e + s]];
            if (adj.edge_face_count(e) == 1) ++boundary_degree[adj.edges[2 * e + s]];
        }
    std::vector<std::uint32_t> leaves;
    for (std::uint32_t v = 0; v < n; ++v)
        if (cut_degree[v] == 1 && boundary_degree[v] == 0) leaves.push_back(v);
    while (!leaves.empty()) {
        const std::uint32_t v = leaves.back();
        leaves.pop_back();
        if (cut_degree[v] != 1) continue;
        for (std::uint32_t w : adj.neighbors(v)) {
            const std::uint32_t e = adj.find_edge(v, w);
            if (!cut[e]) continue;
            cut[e] = 0;
            --cut_degree[v];
            if (--cut_degree[w] == 1 && boundary_degree[w] == 0) leaves.push_back(w);
            break;
        }
    }
    return cut;
}

std::vector<std::uint8_t> cut_vertices(const MeshAdjacency& adj, const std::vector<std::uint8_t>& cut) {
    std::vector<std::uint8_t> on(adj.vertex_count(), 0);
    for (std::size_t e = 0; e < adj.edge_count(); ++e)
        if (cut[e] || adj.edge_face_count(e) == 1) on[adj.edges[2 * e]] = on[adj.edges[2 * e + 1]] = 1;
    return on;
}

PathTree shortest_paths(const Mesh& mesh, const MeshAdjacency& adj, const std::vector<std::uint8_t>& sources) {
    const std::size_t n = adj.vertex_count();
    PathTree t;
    t.distance.assign(n, std::numeric_limits<double>::infinity());
    t.previous.assign(n, kInvalidIndex);
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
    for (std::uint32_t v = 0; v < n; ++v)
        if (sources[v]) t.distance[v] = 0.0, open.push({0.0, v});
    while (!open.empty()) {
        const auto [d, v] = open.top();
        open.pop();
        if (d > t.distance[v]) continue;
        for (std::uint32_t w : adj.neighbors(v)) {
            const double through = d + glm::distance(mesh.positions[v], mesh.positions[w]);
            if (through < t.distance[w]) {
                t.distance[w] = through;
                t.previous[w] = v;
                open.push({through, w});
            }
        }
    }
    return t;
}

std::size_t add_path(const MeshAdjacency& adj, const PathTree& tree, std::uint32_t from,
                     std::vector<std::uint8_t>& cut) {
    std::size_t added = 0;
    for (std::uint32_t v = from; tree.previous[v] != kInvalidIndex; v = tree.previous[v]) {
        std::uint8_t& on = cut[adj.find_edge(v, tree.previous[v])];
        added += !on;
        on = 1;
    }
    return added;
}

std::size_t add_seam(const Mesh& mesh, const MeshAdjacency& adj, std::vector<std::uint8_t>& cut) {
    auto farthest = [&](const PathTree& t) {
        std::uint32_t best = 0;
        for (std::uint32_t v = 0; v < t.distance.size(); ++v)
            if (t.distance[v] != std::numeric_limits<double>::infinity() && t.distance[v] > t.distance[best]) best = v;
        return best;
    };
    std::vector<std::uint8_t> source(adj.vertex_count(), 0);
    if (source.empty()) return 0;
    source[0] = 1;
    const std::uint32_t a = farthest(shortest_paths(mesh, adj, source));
    source[0] = 0;
    source[a] = 1;
    const PathTree from_a = shortest_paths(mesh, adj, source);
    const std::uint32_t b = farthest(from_a);
    std::size_t edges = add_path(adj, from_a, b, cut);
    // One edge opens nothing: neither end has a second wedge to part the two faces. Gu et al. cut
    // two edges where the mesh is that small.
    if (edges == 1)
        for (std::uint32_t c : adj.neighbors(b))
            if (c != a) {
                cut[adj.find_edge(b, c)] = 1;
                return 2;
            }
    return edges;
}

OpenedMesh open_along(const Mesh& mesh, const MeshAdjacency& adj, const std::vector<std::uint8_t>& cut) {
    // Face corners (3f + k) joined across every closed interior edge are one copy of their vertex.
    std::vector<std::uint32_t> parent(3 * mesh.face_count());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](std::uint32_t c) {
        while (parent[c] != c) c = parent[c] = parent[parent[c]];
        return c;
    };
    auto corner = [&](std::uint32_t f, std::uint32_t v) {
        const glm::uvec3& t = mesh.triangles[f];
        return 3 * f + (t[0] == v ? 0u : t[1] == v ? 1u : 2u);
    };
    for (std::size_t e = 0; e < adj.edge_count(); ++e) {
        if (cut[e] || adj.edge_face_count(e) != 2) continue;
        const auto f = adj.faces_of_edge(e);
        for (int s = 0; s < 2; ++s) {
            const std::uint32_t v = adj.edges[2 * e + s];
            parent[root(corner(f[0], v))] = root(corner(f[1], v));
        }
    }
    OpenedMesh out;
    std::vector<std::uint32_t> copy(parent.size(), kInvalidIndex);
    out.disk.triangles.resize(mesh.face_count());
    for (std::uint32_t c = 0; c < parent.size(); ++c) {
        std::uint32_t& id = copy[root(c)];
        const std::uint32_t v = mesh.triangles[c / 3][c % 3];
        if (id == kInvalidIndex) {
            id = std::uint32_t(out.source.size());
            out.source.push_back(v);
            out.disk.positions.push_back(mesh.positions[v]);
            if (mesh.has_normals()) out.disk.normals.push_back(mesh.normals[v]);
            if (mesh.has_texcoords()) out.disk.texcoords.push_back(mesh.texcoords[v]);
        }
        out.disk.triangles[c / 3][c % 3] = id;
    }
    return out;
}

std::size_t split_dividing_edges(OpenedMesh& opened) {
    Mesh& disk = opened.disk;
    const MeshAdjacency adj = build_adjacency(disk);
    std::vector<std::uint8_t> on_boundary(disk.vertex_count(), 0);
    for (std::size_t e = 0; e < adj.edge_count(); ++e)
        if (adj.edge_face_count(e) == 1) on_boundary[adj.edges[2 * e]] = on_boundary[adj.edges[2 * e + 1]] = 1;
    std::vector<std::uint32_t> midpoint(adj.edge_count(), kInvalidIndex);
    const bool normals = disk.has_normals(), texcoords = disk.has_texcoords();
    std::size_t split = 0;
    for (std::size_t e = 0; e < adj.edge_count(); ++e) {
        const std::uint32_t a = adj.edges[2 * e], b = adj.edges[2 * e + 1];
        if (adj.edge_face_count(e) != 2 || !on_boundary[a] || !on_boundary[b]) continue;
        midpoint[e] = std::uint32_t(disk.positions.size());
        disk.positions.push_back(0.5 * (disk.positions[a] + disk.positions[b]));
        if (normals) disk.normals.push_back(glm::normalize(disk.normals[a] + disk.normals[b]));
        if (texcoords) disk.texcoords.push_back(0.5 * (disk.texcoords[a] + disk.texcoords[b]));
        opened.source.push_back(kInvalidIndex);
        ++split;
    }
    if (split == 0) return 0;
    std::vector<glm::uvec3> faces;
    faces.reserve(disk.triangles.size() + 2 * split);
    for (std::size_t f = 0; f < disk.triangles.size(); ++f) {
        const glm::uvec3 t = disk.triangles[f];
        // m[k]: the midpoint of the edge from corner k to corner k + 1, if split.
        std::uint32_t m[3];
        int count = 0, first = -1;
        for (int k = 0; k < 3; ++k) {
            m[k] = midpoint[adj.face_edges[3 * f + k]];
            if (m[k] != kInvalidIndex) ++count, first = first < 0 ? k : first;
        }
        if (count == 0) {
            faces.push_back(t);
        } else if (count == 3) {
            faces.push_back({t[0], m[0], m[2]});
            faces.push_back({m[0], t[1], m[1]});
            faces.push_back({m[2], m[1], t[2]});
            faces.push_back({m[0], m[1], m[2]});
        } else {
            // Turned so that corner 0 starts a split edge, and with two, the other is edge 1.
            int r = first;
            if (count == 2 && m[(r + 1) % 3] == kInvalidIndex) r = (r + 2) % 3;
            const std::uint32_t a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
            const std::uint32_t ab = m[r], bc = m[(r + 1) % 3];
            if (count == 1) {
                faces.push_back({a, ab, c});
                faces.push_back({ab, b, c});
            } else {
                faces.push_back({ab, b, bc});
                faces.push_back({a, ab, bc});
                faces.push_back({a, bc, c});
            }
        }
    }
    disk.triangles = std::move(faces);
    return split;
}

}  // namespace gimg::geo

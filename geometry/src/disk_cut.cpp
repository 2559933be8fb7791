#include "gimg/geometry/disk_cut.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>

namespace gimg::geo {

namespace {

struct Dsu {
    std::vector<std::uint32_t> parent;
    explicit Dsu(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    std::uint32_t root(std::uint32_t c) {
        while (parent[c] != c) c = parent[c] = parent[parent[c]];
        return c;
    }
};

double edge_length(const Mesh& mesh, const MeshAdjacency& adj, std::size_t e) {
    return glm::distance(mesh.positions[adj.edges[2 * e]], mesh.positions[adj.edges[2 * e + 1]]);
}

std::uint32_t farthest(const PathTree& t) {
    std::uint32_t best = 0;
    for (std::uint32_t v = 0; v < t.distance.size(); ++v)
        if (std::isfinite(t.distance[v]) && t.distance[v] > t.distance[best]) best = v;
    return best;
}

// The vertex with the shortest way to the farther of two far vertices: roughly the surface's middle,
// so that the loops through it are short.
std::uint32_t middle_vertex(const Mesh& mesh, const MeshAdjacency& adj) {
    std::vector<std::uint8_t> source(adj.vertex_count(), 0);
    source[0] = 1;
    const std::uint32_t a = farthest(shortest_paths(mesh, adj, source, true));
    std::fill(source.begin(), source.end(), 0);
    source[a] = 1;
    const PathTree from_a = shortest_paths(mesh, adj, source, true);
    std::fill(source.begin(), source.end(), 0);
    source[farthest(from_a)] = 1;
    const PathTree from_b = shortest_paths(mesh, adj, source, true);
    std::uint32_t middle = 0;
    for (std::uint32_t v = 1; v < source.size(); ++v)
        if (std::max(from_a.distance[v], from_b.distance[v]) <
            std::max(from_a.distance[middle], from_b.distance[middle]))
            middle = v;
    return middle;
}

// Every interior edge but those a spanning tree of the faces crosses (Gu et al.): grown breadth
// first from face 0.
std::vector<std::uint8_t> face_tree_cut(const Mesh& mesh, const MeshAdjacency& adj) {
    const std::size_t faces = mesh.face_count();
    std::vector<std::uint8_t> cut(adj.edge_count(), 0);
    for (std::size_t e = 0; e < cut.size(); ++e) cut[e] = adj.edge_face_count(e) == 2;
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
    return cut;
}

// The same with the tree of faces crossing every edge but those of the tree of shortest paths from
// the middle (holes drawn to points), taking first the edges that close the longest loops: the 2g
// edges left close the greedy shortest system of loops through the middle (Erickson and Whittlesey
// 2005).
std::vector<std::uint8_t> shortest_loops_cut(const Mesh& mesh, const MeshAdjacency& adj) {
    const std::size_t n = adj.vertex_count(), edges = adj.edge_count();
    std::vector<std::uint8_t> cut(edges, 0);
    if (n == 0) return cut;
    std::vector<std::uint8_t> source(n, 0);
    source[middle_vertex(mesh, adj)] = 1;
    const PathTree tree = shortest_paths(mesh, adj, source, true);
    std::vector<std::uint8_t> in_tree(edges, 0);
    for (std::uint32_t v = 0; v < n; ++v)
        if (tree.previous[v] != kInvalidIndex) in_tree[adj.find_edge(v, tree.previous[v])] = 1;
    std::vector<std::uint32_t> others;
    for (std::uint32_t e = 0; e < edges; ++e)
        if (adj.edge_face_count(e) == 2) {
            cut[e] = 1;
            if (!in_tree[e]) others.push_back(e);
        }
    std::vector<double> loop(edges, 0.0);
    for (std::uint32_t e : others)
        loop[e] = tree.distance[adj.edges[2 * e]] + tree.distance[adj.edges[2 * e + 1]] + edge_length(mesh, adj, e);
    std::stable_sort(others.begin(), others.end(), [&](std::uint32_t a, std::uint32_t b) { return loop[a] > loop[b]; });
    Dsu faces(mesh.face_count());
    for (std::uint32_t e : others) {
        const auto f = adj.faces_of_edge(e);
        const std::uint32_t a = faces.root(f[0]), b = faces.root(f[1]);
        if (a != b) faces.parent[a] = b, cut[e] = 0;
    }
    return cut;
}

}  // namespace

const char* cut_graph_name(CutGraph kind) { return kind == CutGraph::FaceTree ? "face tree" : "shortest loops"; }

std::vector<std::uint8_t> initial_cut(const Mesh& mesh, const MeshAdjacency& adj, CutGraph kind) {
    std::vector<std::uint8_t> cut =
        kind == CutGraph::FaceTree ? face_tree_cut(mesh, adj) : shortest_loops_cut(mesh, adj);
    // Prune dangling branches: a cut edge at a vertex with no other cut or boundary edge opens
    // nothing that the rest does not.
    const std::size_t n = adj.vertex_count(), edges = adj.edge_count();
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

PathTree shortest_paths(const Mesh& mesh, const MeshAdjacency& adj, const std::vector<std::uint8_t>& sources,
                        bool free_rims) {
    const std::size_t n = adj.vertex_count();
    PathTree t;
    t.distance.assign(n, std::numeric_limits<double>::infinity());
    t.previous.assign(n, kInvalidIndex);
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
    for (std::uint32_t v = 0; v < n; ++v)
        if (sources[v]) t.distance[v] = 0.0, open.push({0.0, v});
    std::vector<std::uint8_t> entered(free_rims ? n : 0, 0);
    std::vector<std::uint32_t> rim;
    while (!open.empty()) {
        const auto [d, v] = open.top();
        open.pop();
        if (d > t.distance[v]) continue;
        // The first vertex reached on a rim reaches all of it, along the rim: the tree enters every
        // hole once.
        if (free_rims && !entered[v]) {
            entered[v] = 1;
            rim.assign(1, v);
            while (!rim.empty()) {
                const std::uint32_t u = rim.back();
                rim.pop_back();
                for (std::uint32_t w : adj.neighbors(u))
                    if (!entered[w] && adj.edge_face_count(adj.find_edge(u, w)) == 1) {
                        entered[w] = 1;
                        t.distance[w] = d;
                        t.previous[w] = u;
                        open.push({d, w});
                        rim.push_back(w);
                    }
            }
        }
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

std::size_t zip_closed_in(const Mesh& mesh, const MeshAdjacency& adj, std::vector<std::uint8_t>& cut) {
    const std::size_t edges = adj.edge_count();
    auto open = [&](std::size_t e) { return cut[e] || adj.edge_face_count(e) == 1; };
    std::vector<std::uint32_t> open_degree(adj.vertex_count(), 0);
    for (std::size_t e = 0; e < edges; ++e)
        if (open(e)) ++open_degree[adj.edges[2 * e]], ++open_degree[adj.edges[2 * e + 1]];
    std::size_t moves = 0;
    for (bool moved = true; moved;) {
        moved = false;
        const OpenedMesh opened = open_along(mesh, adj, cut);
        const Mesh& disk = opened.disk;
        const MeshAdjacency dadj = build_adjacency(disk);
        std::vector<std::uint8_t> rim(disk.vertex_count(), 0);
        for (std::size_t e = 0; e < dadj.edge_count(); ++e)
            if (dadj.edge_face_count(e) == 1) rim[dadj.edges[2 * e]] = rim[dadj.edges[2 * e + 1]] = 1;
        // The closed-in faces (every corner on the disk's rim), grouped across the disk's edges.
        const std::size_t faces = disk.face_count();
        std::vector<std::uint32_t> region(faces, kInvalidIndex);
        auto closed_in = [&](std::uint32_t f) {
            const glm::uvec3& t = disk.triangles[f];
            return rim[t[0]] && rim[t[1]] && rim[t[2]];
        };
        auto across = [&](std::uint32_t f, std::uint32_t e) {
            const auto both = dadj.faces_of_edge(e);
            return both[0] == f ? both[1] : both[0];
        };
        std::vector<std::uint8_t> touched(edges, 0);  // edges a move of this pass changed or relies on
        for (std::uint32_t seed = 0; seed < faces; ++seed) {
            if (region[seed] != kInvalidIndex || !closed_in(seed)) continue;
            std::vector<std::uint32_t> members{seed}, arc, exits;
            region[seed] = seed;
            for (std::size_t i = 0; i < members.size(); ++i)
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t e = dadj.face_edges[3 * members[i] + k];
                    if (dadj.edge_face_count(e) == 1) {
                        arc.push_back(e);
                        continue;
                    }
                    const std::uint32_t g = across(members[i], e);
                    if (!closed_in(g))
                        exits.push_back(e);
                    else if (region[g] == kInvalidIndex)
                        region[g] = seed, members.push_back(g);
                }
            // A strip that meets the rest of the disk at one edge (a, b): its rim is one arc from a
            // to b. Walk it, as the mesh's edges.
            if (exits.size() != 1) continue;
            const std::uint32_t a = dadj.edges[2 * exits[0]], b = dadj.edges[2 * exits[0] + 1];
            std::vector<std::uint32_t> path{a}, mesh_edges;
            std::vector<std::uint8_t> used(arc.size(), 0);
            for (bool step = true; step && path.back() != b;) {
                step = false;
                for (std::size_t i = 0; i < arc.size() && !step; ++i) {
                    const std::uint32_t u = dadj.edges[2 * arc[i]], w = dadj.edges[2 * arc[i] + 1];
                    if (used[i] || (u != path.back() && w != path.back())) continue;
                    used[i] = 1, step = true;
                    path.push_back(u == path.back() ? w : u);
                    mesh_edges.push_back(adj.find_edge(opened.source[u], opened.source[w]));
                }
            }
            const std::uint32_t chord = adj.find_edge(opened.source[a], opened.source[b]);
            if (path.back() != b || mesh_edges.size() != arc.size() || chord == kInvalidIndex || touched[chord])
                continue;
            if (std::any_of(mesh_edges.begin(), mesh_edges.end(), [&](std::uint32_t e) { return touched[e]; }))
                continue;
            // Its longest run along one cut path (cut edges meeting at vertices with no third cut or
            // rim edge), whose other side lies outside the strip.
            double best = edge_length(mesh, adj, chord);
            std::size_t from = 0, to = 0;
            for (std::size_t i = 0; i < mesh_edges.size();) {
                std::size_t j = i;
                double length = 0.0;
                while (j < mesh_edges.size() && cut[mesh_edges[j]] &&
                       (j == i || open_degree[opened.source[path[j]]] == 2)) {
                    const auto two = adj.faces_of_edge(mesh_edges[j]);
                    if (region[two[0]] == seed && region[two[1]] == seed) break;
                    length += edge_length(mesh, adj, mesh_edges[j++]);
                }
                if (length > best) best = length, from = i, to = j;
                i = std::max(j, i + 1);
            }
            if (from == to) continue;
            // A seam of two edges round one face would become one edge, which opens nothing.
            const std::uint32_t c0 = adj.edges[2 * chord], c1 = adj.edges[2 * chord + 1];
            const auto left = [&](std::uint32_t v) {
                std::uint32_t d = open_degree[v];
                for (std::size_t i = from; i < to; ++i)
                    d -= adj.edges[2 * mesh_edges[i]] == v || adj.edges[2 * mesh_edges[i] + 1] == v;
                return d;
            };
            if (left(c0) == 0 && left(c1) == 0) continue;
            // Glue the strip to the run's other side and part it from the rest at (a, b): the
            // surface stays a disk and the cut is shorter.
            for (std::uint32_t e : mesh_edges) touched[e] = 1;
            touched[chord] = 1;
            for (std::size_t i = from; i < to; ++i) {
                cut[mesh_edges[i]] = 0;
                --open_degree[adj.edges[2 * mesh_edges[i]]], --open_degree[adj.edges[2 * mesh_edges[i] + 1]];
            }
            cut[chord] = 1;
            ++open_degree[adj.edges[2 * chord]], ++open_degree[adj.edges[2 * chord + 1]];
            ++moves;
            moved = true;
        }
    }
    return moves;
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

std::size_t split_short_boundary(OpenedMesh& opened) {
    Mesh& disk = opened.disk;
    std::size_t split = 0;
    for (;;) {
        const MeshAdjacency adj = build_adjacency(disk);
        std::size_t boundary = 0, longest = kInvalidIndex;
        double length = -1.0;
        for (std::size_t e = 0; e < adj.edge_count(); ++e) {
            if (adj.edge_face_count(e) != 1) continue;
            ++boundary;
            const double l = glm::distance(disk.positions[adj.edges[2 * e]], disk.positions[adj.edges[2 * e + 1]]);
            if (l > length) length = l, longest = e;
        }
        if (boundary == 0 || boundary >= 4) return split;
        const std::uint32_t f = adj.faces_of_edge(longest)[0];
        const glm::uvec3 t = disk.triangles[f];
        int k = 0;  // the face's side from corner k to corner k + 1 is the edge
        while (adj.face_edges[3 * f + k] != longest) ++k;
        const std::uint32_t a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
        const auto m = std::uint32_t(disk.positions.size());
        disk.positions.push_back(0.5 * (disk.positions[a] + disk.positions[b]));
        if (disk.normals.size() + 1 == disk.positions.size())
            disk.normals.push_back(glm::normalize(disk.normals[a] + disk.normals[b]));
        if (disk.texcoords.size() + 1 == disk.positions.size())
            disk.texcoords.push_back(0.5 * (disk.texcoords[a] + disk.texcoords[b]));
        opened.source.push_back(kInvalidIndex);
        disk.triangles[f] = {a, m, c};
        disk.triangles.push_back({m, b, c});
        ++split;
    }
}

}  // namespace gimg::geo

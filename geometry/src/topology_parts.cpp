#include "topology_parts.h"

#include <algorithm>
#include <numeric>
#include <utility>

namespace gimg::geo::topo {

UnionFind::UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }

std::uint32_t UnionFind::find(std::uint32_t x) {
    while (parent_[x] != x) {
        parent_[x] = parent_[parent_[x]];  // path halving
        x = parent_[x];
    }
    return x;
}

void UnionFind::unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a > b) std::swap(a, b);
    parent_[b] = a;  // the smaller index is the root: deterministic
}

EdgeTable build_edge_table(const Mesh& mesh, const std::vector<std::uint8_t>& collapsed) {
    // Sides bucketed by their smaller vertex (a counting sort, in face order), then each bucket,
    // a handful of sides, sorted by (b, face): linear, where one comparison sort of all sides was
    // the largest part of analyze_topology (624K sides on armadillo_loop1).
    const std::size_t n = mesh.positions.size();
    std::vector<std::uint32_t> bucket(n + 1, 0);
    for (const glm::uvec3& tri : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t from = tri[k], to = tri[(k + 1) % 3];
            if (from != to) ++bucket[std::min(from, to) + 1];
        }
    std::partial_sum(bucket.begin(), bucket.end(), bucket.begin());
    EdgeTable t;
    t.sides.resize(bucket[n]);
    std::vector<std::uint32_t> fill(bucket.begin(), bucket.end() - 1);
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const glm::uvec3& tri = mesh.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t from = tri[k], to = tri[(k + 1) % 3];
            if (from == to) continue;
            const std::uint32_t a = std::min(from, to);
            t.sides[fill[a]++] = {a, std::max(from, to), f, from < to, collapsed[f] == 0};
        }
    }
    for (std::size_t v = 0; v < n; ++v)
        std::sort(t.sides.begin() + bucket[v], t.sides.begin() + bucket[v + 1],
                  [](const Side& x, const Side& y) { return x.b != y.b ? x.b < y.b : x.face < y.face; });
    t.edge_begin.reserve(t.sides.size() / 2 + 2);
    for (std::uint32_t i = 0; i < t.sides.size(); ++i) {
        if (i == 0 || t.sides[i].a != t.sides[i - 1].a || t.sides[i].b != t.sides[i - 1].b) {
            t.edge_begin.push_back(i);
            t.surface.push_back(0);
        }
        if (t.sides[i].surface) ++t.surface.back();
    }
    t.edge_begin.push_back(static_cast<std::uint32_t>(t.sides.size()));
    return t;
}

std::uint32_t Fans::fan_of(std::uint32_t vertex, std::uint32_t face) const {
    for (std::uint32_t i = begin[vertex]; i < begin[vertex + 1]; ++i) {
        if (faces[i] == face) return fan[i];
    }
    return 0;
}

Fans build_fans(const Mesh& mesh, const std::vector<std::uint8_t>& collapsed) {
    const std::size_t n = mesh.positions.size();
    Fans fans;
    fans.begin.assign(n + 1, 0);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        if (collapsed[f]) continue;
        for (int k = 0; k < 3; ++k) ++fans.begin[mesh.triangles[f][k] + 1];
    }
    std::partial_sum(fans.begin.begin(), fans.begin.end(), fans.begin.begin());
    fans.faces.resize(fans.begin[n]);
    std::vector<std::uint32_t> fill(fans.begin.begin(), fans.begin.end() - 1);
    for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        if (collapsed[f]) continue;
        for (int k = 0; k < 3; ++k) fans.faces[fill[mesh.triangles[f][k]]++] = f;
    }
    fans.fan.assign(fans.faces.size(), 0);
    fans.count.assign(n, 0);

    // Per vertex: join faces that share an other vertex (that is, an edge at this vertex).
    std::vector<std::pair<std::uint32_t, std::uint32_t>> neighbours;  // (other vertex, local face)
    std::vector<std::uint32_t> local_root;
    for (std::uint32_t v = 0; v < n; ++v) {
        const std::uint32_t b = fans.begin[v], e = fans.begin[v + 1];
        if (b == e) continue;
        neighbours.clear();
        for (std::uint32_t i = b; i < e; ++i) {
            const glm::uvec3& tri = mesh.triangles[fans.faces[i]];
            for (int k = 0; k < 3; ++k) {
                if (tri[k] != v) neighbours.emplace_back(tri[k], i - b);
            }
        }
        std::sort(neighbours.begin(), neighbours.end());
        UnionFind local(e - b);
        for (std::size_t j = 1; j < neighbours.size(); ++j) {
            if (neighbours[j].first == neighbours[j - 1].first)
                local.unite(neighbours[j].second, neighbours[j - 1].second);
        }
        // Number the fans 0, 1, ... in the order of their first face.
        local_root.assign(e - b, UINT32_MAX);
        std::uint32_t fans_here = 0;
        for (std::uint32_t i = 0; i < e - b; ++i) {
            const std::uint32_t root = local.find(i);
            if (local_root[root] == UINT32_MAX) local_root[root] = fans_here++;
            fans.fan[b + i] = local_root[root];
        }
        fans.count[v] = fans_here;
    }
    return fans;
}

std::vector<std::uint32_t> boundary_loops(const EdgeTable& edges, const Fans& fans) {
    // The ends of every boundary edge, keyed by (vertex, fan of the edge's face at that vertex).
    struct End {
        std::uint32_t vertex, fan, edge;
    };
    std::vector<End> ends;
    std::vector<std::uint32_t> boundary;  // edge numbers of boundary edges
    for (std::uint32_t e = 0; e < edges.edge_count(); ++e) {
        if (edges.surface[e] != 1) continue;
        std::uint32_t face = 0;
        for (std::uint32_t i = edges.edge_begin[e]; i < edges.edge_begin[e + 1]; ++i) {
            if (edges.sides[i].surface) face = edges.sides[i].face;
        }
        const Side& s = edges.sides[edges.edge_begin[e]];
        const auto id = static_cast<std::uint32_t>(boundary.size());
        boundary.push_back(e);
        ends.push_back({s.a, fans.fan_of(s.a, face), id});
        ends.push_back({s.b, fans.fan_of(s.b, face), id});
    }
    std::sort(ends.begin(), ends.end(), [](const End& x, const End& y) {
        if (x.vertex != y.vertex) return x.vertex < y.vertex;
        if (x.fan != y.fan) return x.fan < y.fan;
        return x.edge < y.edge;
    });
    // Chain the ends meeting at a vertex: within a fan first (at a manifold boundary vertex its
    // one fan holds exactly the two boundary edges), then whatever is left at that vertex.
    UnionFind chains(boundary.size());
    std::vector<std::uint32_t> leftover;
    for (std::size_t i = 0; i < ends.size();) {
        std::size_t vertex_end = i;
        while (vertex_end < ends.size() && ends[vertex_end].vertex == ends[i].vertex) ++vertex_end;
        leftover.clear();
        for (std::size_t j = i; j < vertex_end;) {
            std::size_t fan_end = j;
            while (fan_end < vertex_end && ends[fan_end].fan == ends[j].fan) ++fan_end;
            std::size_t k = j;
            for (; k + 1 < fan_end; k += 2) chains.unite(ends[k].edge, ends[k + 1].edge);
            if (k < fan_end) leftover.push_back(ends[k].edge);
            j = fan_end;
        }
        for (std::size_t k = 0; k + 1 < leftover.size(); k += 2) chains.unite(leftover[k], leftover[k + 1]);
        i = vertex_end;
    }
    std::vector<std::uint32_t> loops;  // a vertex of each loop
    for (std::uint32_t id = 0; id < boundary.size(); ++id) {
        if (chains.find(id) == id) loops.push_back(edges.sides[edges.edge_begin[boundary[id]]].a);
    }
    return loops;
}

}  // namespace gimg::geo::topo

// repair_mesh (repair.h): steps 1-4 and 6 on the flat triangle list, which holds every face of a
// soup; step 5, which needs a halfedge structure, is repair_zero_area.cpp.
#include "gimg/geometry/repair.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/weld.h"

#include "repair_parts.h"
#include "topology_parts.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <utility>

namespace gimg::geo {

using detail::kNoVertex;

namespace {

void check_input(const Mesh& mesh) {
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (mesh.triangles[f][k] >= mesh.positions.size())
                throw InputError("repair: triangle " + std::to_string(f) + " names vertex " +
                                 std::to_string(mesh.triangles[f][k]) + ", but the mesh has " +
                                 std::to_string(mesh.positions.size()) + " vertices");
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3& p = mesh.positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError("repair: vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
    }
}

template <class Keep>
void keep_faces(Mesh& mesh, Keep&& keep) {
    std::size_t out = 0;
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
        if (keep(f)) mesh.triangles[out++] = mesh.triangles[f];
    mesh.triangles.resize(out);
}

// Step 2.
void remove_collapsed_and_duplicates(Mesh& mesh, RepairReport& report) {
    std::set<std::array<std::uint32_t, 3>> seen;
    keep_faces(mesh, [&](std::size_t f) {
        const glm::uvec3& t = mesh.triangles[f];
        if (t.x == t.y || t.y == t.z || t.z == t.x) {
            ++report.collapsed_faces;
            return false;
        }
        std::array<std::uint32_t, 3> key{t.x, t.y, t.z};
        std::sort(key.begin(), key.end());
        if (!seen.insert(key).second) {
            ++report.duplicate_faces;
            return false;
        }
        return true;
    });
}

// Step 3: every face of a piece turned to agree with the walk from the piece's first face across
// edges of two faces; then each piece keeps the orientation of the larger part of its area.
void turn_faces(Mesh& mesh, RepairReport& report) {
    const std::size_t nf = mesh.triangles.size();
    const topo::EdgeTable edges = topo::build_edge_table(mesh, std::vector<std::uint8_t>(nf, 0));
    struct Link {
        std::uint32_t other;
        bool same_direction;  // both faces go along the edge the same way: one must turn
        std::uint32_t edge;
    };
    std::vector<std::vector<Link>> links(nf);
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        const std::uint32_t b = edges.edge_begin[e], count = edges.edge_begin[e + 1] - b;
        if (count != 2) continue;
        const topo::Side &s0 = edges.sides[b], &s1 = edges.sides[b + 1];
        const bool same = s0.forward == s1.forward;
        links[s0.face].push_back({s1.face, same, std::uint32_t(e)});
        links[s1.face].push_back({s0.face, same, std::uint32_t(e)});
    }
    std::vector<std::int8_t> turn(nf, -1);
    std::vector<std::uint32_t> piece(nf, 0), queue;
    std::vector<std::uint8_t> opened(edges.edge_count(), 0);
    std::vector<std::array<double, 2>> area;  // per piece: kept, turned
    for (std::uint32_t seed = 0; seed < nf; ++seed) {
        if (turn[seed] >= 0) continue;
        const std::uint32_t p = std::uint32_t(area.size());
        area.push_back({0.0, 0.0});
        turn[seed] = 0;
        piece[seed] = p;
        queue.assign(1, seed);
        for (std::size_t q = 0; q < queue.size(); ++q) {
            const std::uint32_t f = queue[q];
            for (const Link& l : links[f]) {
                const std::int8_t need = std::int8_t(turn[f] ^ (l.same_direction ? 1 : 0));
                if (turn[l.other] < 0) {
                    turn[l.other] = need;
                    piece[l.other] = p;
                    queue.push_back(l.other);
                } else if (turn[l.other] != need && !opened[l.edge]) {
                    opened[l.edge] = 1;  // the walk met itself turned the other way
                    ++report.opened_edges;
                }
            }
        }
    }
    for (std::size_t f = 0; f < nf; ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        const glm::dvec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
        area[piece[f]][turn[f]] += glm::length(glm::cross(b - a, c - a));
    }
    for (std::size_t f = 0; f < nf; ++f) {
        const bool reverse = area[piece[f]][1] > area[piece[f]][0] ? turn[f] == 0 : turn[f] == 1;
        if (!reverse) continue;
        std::swap(mesh.triangles[f].y, mesh.triangles[f].z);
        ++report.turned_faces;
    }
}

// Two faces joined across an edge of more than two.
struct Pair {
    std::uint32_t f, g;  // faces
    std::uint32_t a, b;  // the edge's vertices
};

// Step 4's pairs: around an edge of more than two faces, each face is paired with the next face met
// turning about the edge from its back (the inside of the solid it bounds), where that face goes
// along the edge the other way; faces left unpaired no longer join across the edge. Two solids
// touching along an edge thus stay two closed surfaces, and a fin on the front of a surface leaves
// the surface whole (one on its back may take a side of the edge from it).
std::vector<Pair> pair_crowded_edges(const Mesh& mesh, RepairReport& report) {
    const std::size_t nf = mesh.triangles.size();
    const topo::EdgeTable edges = topo::build_edge_table(mesh, std::vector<std::uint8_t>(nf, 0));
    std::vector<Pair> pairs;
    struct Around {
        double angle;
        std::uint32_t face;
        bool forward;  // a -> b
    };
    std::vector<Around> around;
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        const std::uint32_t begin = edges.edge_begin[e], end = edges.edge_begin[e + 1];
        if (end - begin <= 2) continue;
        const std::uint32_t a = edges.sides[begin].a, b = edges.sides[begin].b;
        const glm::dvec3 pa = mesh.positions[a], axis = glm::normalize(mesh.positions[b] - pa);
        const glm::dvec3 u =
            glm::normalize(glm::cross(axis, std::abs(axis.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
        const glm::dvec3 v = glm::cross(axis, u);
        around.clear();
        for (std::uint32_t i = begin; i < end; ++i) {
            const glm::uvec3& t = mesh.triangles[edges.sides[i].face];
            const std::uint32_t c = t.x != a && t.x != b ? t.x : t.y != a && t.y != b ? t.y : t.z;
            const glm::dvec3 w = mesh.positions[c] - pa;
            around.push_back({std::atan2(glm::dot(w, v), glm::dot(w, u)), edges.sides[i].face, edges.sides[i].forward});
        }
        std::sort(around.begin(), around.end(), [](const Around& x, const Around& y) { return x.angle < y.angle; });
        // A face going a -> b has its back towards decreasing angles, one going b -> a towards
        // increasing ones: a backward face pairs with the next face up when that one goes forward.
        const std::size_t k = around.size();
        std::size_t paired = 0;
        for (std::size_t i = 0; i < k; ++i) {
            const Around &x = around[i], &y = around[(i + 1) % k];
            if (x.forward || !y.forward) continue;
            pairs.push_back({x.face, y.face, a, b});
            paired += 2;
        }
        if (paired < k) ++report.opened_edges;
    }
    return pairs;
}

// Step 4: corners of one vertex joined through edges of two faces that agree and through the
// pairs; each class of corners beyond a vertex's first becomes a copy of it.
void split_fans(Mesh& mesh, const std::vector<Pair>& pairs, RepairReport& report) {
    const std::size_t nf = mesh.triangles.size(), nv = mesh.positions.size();
    const topo::EdgeTable edges = topo::build_edge_table(mesh, std::vector<std::uint8_t>(nf, 0));
    topo::UnionFind corners(3 * nf);
    auto corner = [&](std::uint32_t f, std::uint32_t v) {
        const glm::uvec3& t = mesh.triangles[f];
        return 3 * f + (t.x == v ? 0u : t.y == v ? 1u : 2u);
    };
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        const std::uint32_t b = edges.edge_begin[e];
        if (edges.edge_begin[e + 1] - b != 2) continue;
        const topo::Side &s0 = edges.sides[b], &s1 = edges.sides[b + 1];
        if (s0.forward == s1.forward) continue;
        corners.unite(corner(s0.face, s0.a), corner(s1.face, s0.a));
        corners.unite(corner(s0.face, s0.b), corner(s1.face, s0.b));
    }
    for (const Pair& p : pairs) {
        corners.unite(corner(p.f, p.a), corner(p.g, p.a));
        corners.unite(corner(p.f, p.b), corner(p.g, p.b));
    }
    // The class of a vertex's first corner keeps the vertex.
    std::vector<std::uint32_t> owner(nv, kNoVertex), vertex_of_class(3 * nf, kNoVertex);
    for (std::uint32_t c = 0; c < 3 * nf; ++c) {
        const std::uint32_t v = mesh.triangles[c / 3][c % 3], root = corners.find(c);
        if (vertex_of_class[root] == kNoVertex) {
            if (owner[v] == kNoVertex) {
                owner[v] = root;
                vertex_of_class[root] = v;
            } else {
                vertex_of_class[root] = std::uint32_t(mesh.positions.size());
                detail::copy_vertex(mesh, v);
                ++report.split_vertices;
            }
        }
        mesh.triangles[c / 3][c % 3] = vertex_of_class[root];
    }
}

// After the split, an edge can still have more than two faces, or two that disagree, where faces
// met across it only through other edges at both its ends. Keeps each such edge's first face, and
// its second where that agrees; returns whether it removed any.
bool drop_faces_on_bad_edges(Mesh& mesh, RepairReport& report) {
    const std::size_t nf = mesh.triangles.size();
    const topo::EdgeTable edges = topo::build_edge_table(mesh, std::vector<std::uint8_t>(nf, 0));
    std::vector<std::uint8_t> drop(nf, 0);
    bool any = false;
    for (std::size_t e = 0; e < edges.edge_count(); ++e) {
        const std::uint32_t b = edges.edge_begin[e], end = edges.edge_begin[e + 1];
        if (end - b < 2 || (end - b == 2 && edges.sides[b].forward != edges.sides[b + 1].forward)) continue;
        for (std::uint32_t i = b + 1; i < end; ++i) {
            if (i == b + 1 && edges.sides[i].forward != edges.sides[b].forward) continue;
            if (!drop[edges.sides[i].face]) ++report.dropped_faces;
            drop[edges.sides[i].face] = 1;
            any = true;
        }
    }
    keep_faces(mesh, [&](std::size_t f) { return !drop[f]; });
    return any;
}

// Step 6: the piece of most faces (the first of those), pieces joined through vertices.
void keep_largest_piece(Mesh& mesh, RepairReport& report) {
    topo::UnionFind pieces(mesh.positions.size());
    for (const glm::uvec3& t : mesh.triangles) {
        pieces.unite(t.x, t.y);
        pieces.unite(t.y, t.z);
    }
    std::vector<std::size_t> faces(mesh.positions.size(), 0);
    std::vector<std::uint32_t> order;  // roots by their first face
    for (const glm::uvec3& t : mesh.triangles) {
        const std::uint32_t r = pieces.find(t.x);
        if (faces[r]++ == 0) order.push_back(r);
    }
    if (order.empty()) return;
    std::uint32_t best = order.front();
    for (std::uint32_t r : order)
        if (faces[r] > faces[best]) best = r;
    report.dropped_pieces = order.size() - 1;
    keep_faces(mesh, [&](std::size_t f) { return pieces.find(mesh.triangles[f].x) == best; });
}

void remove_unused_vertices(Mesh& mesh, RepairReport& report) {
    const std::size_t nv = mesh.positions.size();
    std::vector<std::uint32_t> remap(nv, kNoVertex);
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) remap[t[k]] = 0;
    std::uint32_t kept = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        if (remap[v] == kNoVertex) continue;
        remap[v] = kept;
        mesh.positions[kept] = mesh.positions[v];
        if (mesh.has_texcoords()) mesh.texcoords[kept] = mesh.texcoords[v];
        if (mesh.has_normals()) mesh.normals[kept] = mesh.normals[v];
        ++kept;
    }
    report.unused_vertices = nv - kept;
    const bool texcoords = mesh.has_texcoords(), normals = mesh.has_normals();
    mesh.positions.resize(kept);
    if (texcoords) mesh.texcoords.resize(kept);
    if (normals) mesh.normals.resize(kept);
    for (glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) t[k] = remap[t[k]];
}

}  // namespace

namespace detail {

void copy_vertex(Mesh& mesh, std::uint32_t v) {
    const bool texcoords = mesh.has_texcoords(), normals = mesh.has_normals();
    mesh.positions.push_back(mesh.positions[v]);
    if (texcoords) mesh.texcoords.push_back(mesh.texcoords[v]);
    if (normals) mesh.normals.push_back(mesh.normals[v]);
}

}  // namespace detail

bool RepairReport::changed() const {
    return welded_vertices + collapsed_faces + duplicate_faces + turned_faces + split_vertices + dropped_faces +
               flipped_edges + collapsed_edges + dropped_pieces + unused_vertices + zero_area_faces - zero_area_left >
           0;
}

RepairReport repair_mesh(Mesh& mesh, const RepairOptions& options) {
    check_input(mesh);
    if (!mesh.has_texcoords()) mesh.texcoords.clear();
    if (!mesh.has_normals()) mesh.normals.clear();
    RepairReport report;
    if (options.weld) report.welded_vertices = weld_identical_vertices(mesh);
    remove_collapsed_and_duplicates(mesh, report);
    turn_faces(mesh, report);
    split_fans(mesh, pair_crowded_edges(mesh, report), report);
    while (drop_faces_on_bad_edges(mesh, report)) split_fans(mesh, {}, report);
    detail::remove_zero_area_faces(mesh, report);
    if (options.largest) keep_largest_piece(mesh, report);
    remove_unused_vertices(mesh, report);
    return report;
}

}  // namespace gimg::geo

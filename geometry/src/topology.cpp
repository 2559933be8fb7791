// analyze_topology: see topology.h for the definitions it implements.

#include "gimg/geometry/topology.h"

#include "topology_parts.h"

#include "gimg/geometry/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace gimg::geo {

namespace {

bool is_finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

void check_indices(const Mesh& mesh) {
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            if (mesh.triangles[f][k] >= mesh.positions.size()) {
                throw InputError("triangle " + std::to_string(f) + " names vertex " +
                                 std::to_string(mesh.triangles[f][k]) + ", but the mesh has " +
                                 std::to_string(mesh.positions.size()) + " vertices");
            }
        }
    }
}

void count_faces(const Mesh& mesh, std::vector<std::uint8_t>& collapsed, MeshInfo& info) {
    collapsed.assign(mesh.triangles.size(), 0);
    std::vector<std::array<std::uint32_t, 3>> sorted(mesh.triangles.size());
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            collapsed[f] = 1;
            ++info.collapsed_faces;
        } else if (zero_area_face(mesh, t)) {
            ++info.zero_area_faces;
        }
        sorted[f] = {t[0], t[1], t[2]};
        std::sort(sorted[f].begin(), sorted[f].end());
    }
    info.degenerate_faces = info.collapsed_faces + info.zero_area_faces;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 1; i < sorted.size(); ++i) {
        if (sorted[i] == sorted[i - 1]) ++info.duplicate_faces;
    }
}

// Per face: +1 or -1 relative to the first face reached in its component, through manifold
// edges; records per component whether that succeeded (orientable) and whether no flip was
// needed (oriented).
void check_orientation(const Mesh& mesh, const topo::EdgeTable& edges, const std::vector<std::uint32_t>& face_component,
                       std::vector<ComponentInfo>& components, MeshInfo& info) {
    const std::size_t nf = mesh.triangles.size();
    // Neighbours across manifold edges, with whether the two faces agree there.
    std::vector<std::uint32_t> begin(nf + 1, 0);
    for (std::uint32_t e = 0; e < edges.edge_count(); ++e) {
        if (edges.surface[e] != 2) continue;
        for (std::uint32_t i = edges.edge_begin[e]; i < edges.edge_begin[e + 1]; ++i) {
            if (edges.sides[i].surface) ++begin[edges.sides[i].face + 1];
        }
    }
    std::partial_sum(begin.begin(), begin.end(), begin.begin());
    struct Link {
        std::uint32_t face;
        bool agree;
    };
    std::vector<Link> links(begin[nf]);
    std::vector<std::uint32_t> fill(begin.begin(), begin.end() - 1);
    for (std::uint32_t e = 0; e < edges.edge_count(); ++e) {
        if (edges.surface[e] != 2) continue;
        const topo::Side* pair[2] = {nullptr, nullptr};
        for (std::uint32_t i = edges.edge_begin[e], k = 0; i < edges.edge_begin[e + 1]; ++i) {
            if (edges.sides[i].surface) pair[k++] = &edges.sides[i];
        }
        const bool agree = pair[0]->forward != pair[1]->forward;
        if (!agree) {
            ++info.inconsistent_edges;
            components[face_component[pair[0]->face]].oriented = false;
        }
        links[fill[pair[0]->face]++] = {pair[1]->face, agree};
        links[fill[pair[1]->face]++] = {pair[0]->face, agree};
    }
    std::vector<std::int8_t> sign(nf, 0);
    std::vector<std::uint32_t> stack;
    for (std::uint32_t start = 0; start < nf; ++start) {
        if (sign[start] != 0) continue;
        sign[start] = 1;
        stack.assign(1, start);
        while (!stack.empty()) {
            const std::uint32_t f = stack.back();
            stack.pop_back();
            for (std::uint32_t i = begin[f]; i < begin[f + 1]; ++i) {
                const std::int8_t want = links[i].agree ? sign[f] : static_cast<std::int8_t>(-sign[f]);
                if (sign[links[i].face] == 0) {
                    sign[links[i].face] = want;
                    stack.push_back(links[i].face);
                } else if (sign[links[i].face] != want) {
                    components[face_component[f]].orientable = false;
                }
            }
        }
    }
}

}  // namespace

// Zero area relative to the face's size, so that the test does not depend on the mesh's scale.
bool zero_area_face(const Mesh& mesh, const glm::uvec3& t) {
    return zero_area_triangle(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
}

bool zero_area_triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const double longest = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a), glm::dot(c - b, c - b)});
    return glm::length(glm::cross(b - a, c - a)) <= 1e-12 * longest;
}

MeshInfo analyze_topology(const Mesh& mesh) {
    check_indices(mesh);
    MeshInfo info;
    info.vertices = mesh.positions.size();
    info.faces = mesh.triangles.size();

    bool any_finite = false;
    for (const glm::dvec3& p : mesh.positions) {
        if (!is_finite(p)) {
            ++info.nonfinite_vertices;
            continue;
        }
        info.bbox.min = any_finite ? glm::min(info.bbox.min, p) : p;
        info.bbox.max = any_finite ? glm::max(info.bbox.max, p) : p;
        any_finite = true;
    }

    std::vector<std::uint8_t> collapsed;
    count_faces(mesh, collapsed, info);

    // Components: vertices joined by faces.
    topo::UnionFind joined(mesh.positions.size());
    std::vector<std::uint8_t> used(mesh.positions.size(), 0);
    for (const glm::uvec3& t : mesh.triangles) {
        joined.unite(t[0], t[1]);
        joined.unite(t[0], t[2]);
        used[t[0]] = used[t[1]] = used[t[2]] = 1;
    }
    // Number components in the order of their first face, so results do not depend on hashing.
    std::vector<std::uint32_t> component_of_root(mesh.positions.size(), UINT32_MAX);
    std::vector<std::uint32_t> face_component(mesh.triangles.size());
    std::vector<ComponentInfo> components;
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        const std::uint32_t root = joined.find(mesh.triangles[f][0]);
        if (component_of_root[root] == UINT32_MAX) {
            component_of_root[root] = static_cast<std::uint32_t>(components.size());
            components.emplace_back();
        }
        face_component[f] = component_of_root[root];
        ComponentInfo& c = components[face_component[f]];
        ++c.faces;
        if (!collapsed[f]) ++c.euler_characteristic;  // + F
    }
    auto component_of_vertex = [&](std::uint32_t v) { return component_of_root[joined.find(v)]; };
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
        if (!used[v]) {
            ++info.isolated_vertices;
            continue;
        }
        ComponentInfo& c = components[component_of_vertex(v)];
        ++c.vertices;
        ++c.euler_characteristic;  // + V
    }

    const topo::EdgeTable edges = topo::build_edge_table(mesh, collapsed);
    info.edges = edges.edge_count();
    for (std::uint32_t e = 0; e < edges.edge_count(); ++e) {
        ComponentInfo& c = components[component_of_vertex(edges.sides[edges.edge_begin[e]].a)];
        ++c.edges;
        --c.euler_characteristic;  // - E
        const std::uint32_t s = edges.surface[e];
        if (s == 1) ++info.boundary_edges;
        if (s > 2) ++info.non_manifold_edges;
        if (s == 0) ++info.wire_edges;
        if (s > 2 || s == 0) c.manifold = false;
    }

    const topo::Fans fans = topo::build_fans(mesh, collapsed);
    for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
        if (fans.count[v] > 1) {
            ++info.non_manifold_vertices;
            components[component_of_vertex(v)].manifold = false;
        }
    }
    for (std::uint32_t vertex : topo::boundary_loops(edges, fans)) {
        ++components[component_of_vertex(vertex)].boundary_loops;
        ++info.boundary_loops;
    }
    check_orientation(mesh, edges, face_component, components, info);

    for (ComponentInfo& c : components) {
        const long long twice_genus = 2 - c.euler_characteristic - static_cast<long long>(c.boundary_loops);
        if (c.manifold && c.orientable && twice_genus >= 0 && twice_genus % 2 == 0) c.genus = twice_genus / 2;
        info.manifold = info.manifold && c.manifold;
        info.orientable = info.orientable && c.orientable;
        info.oriented = info.oriented && c.oriented;
    }
    info.closed = info.boundary_edges == 0;
    // Largest first; stable, so equal sizes keep the order of their first face.
    std::stable_sort(components.begin(), components.end(),
                     [](const ComponentInfo& a, const ComponentInfo& b) { return a.faces > b.faces; });
    info.components = components.size();
    info.component_info = std::move(components);
    return info;
}

}  // namespace gimg::geo

// Floater's shape-preserving weights (M. S. Floater, "Parametrization and smooth approximation of
// surface triangulations", CAGD 14, 1997): the barycentric coordinates that the vertex has in its
// one-ring flattened by the geodesic polar map, averaged over the ring's triangles that contain it.
#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/passes/parameterize.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace gimg::passes {

namespace {

// The neighbours of interior vertex v in counter-clockwise order (each face (v, a, b) gives a -> b),
// into `ring`; `steps` is scratch.
void ordered_ring(const geo::Mesh& mesh, const geo::MeshAdjacency& adj, std::uint32_t v,
                  std::vector<std::pair<std::uint32_t, std::uint32_t>>& steps, std::vector<std::uint32_t>& ring) {
    const auto faces = adj.faces_of_vertex(v);
    steps.clear();
    for (std::uint32_t f : faces) {
        const glm::uvec3& t = mesh.triangles[f];
        const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        steps.emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
    }
    ring.assign(1, steps[0].first);
    while (ring.size() < steps.size()) {
        const auto it = std::find_if(steps.begin(), steps.end(), [&](const auto& s) { return s.first == ring.back(); });
        if (it == steps.end()) throw geo::InputError("vertex " + std::to_string(v) + ": its faces do not form a fan");
        ring.push_back(it->second);
    }
}

// Per thread, reused from vertex to vertex.
struct RowScratch {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> steps;
    std::vector<std::uint32_t> ring;
    std::vector<double> angle, lambda, length;
    std::vector<glm::dvec3> direction;
    std::vector<glm::dvec2> q;
};

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

// Floater's weights of interior vertex v into its row of `slot`; 1 when it fell back to chord length.
std::size_t floater_row(const geo::Mesh& mesh, const geo::MeshAdjacency& adj, std::uint32_t v,
                        std::vector<double>& slot, RowScratch& scratch) {
    ordered_ring(mesh, adj, v, scratch.steps, scratch.ring);
    const std::vector<std::uint32_t>& ring = scratch.ring;
    const std::size_t d = ring.size();
    // Geodesic polar map: lengths kept, angles scaled to sum to 2 pi.
    std::vector<double>& angle = scratch.angle;
    std::vector<double>& length = scratch.length;
    std::vector<glm::dvec3>& direction = scratch.direction;
    angle.assign(d + 1, 0.0);
    length.resize(d), direction.resize(d);
    for (std::size_t k = 0; k < d; ++k) {
        const glm::dvec3 e = mesh.positions[ring[k]] - mesh.positions[v];
        length[k] = glm::length(e);
        direction[k] = e / length[k];
    }
    for (std::size_t k = 0; k < d; ++k)
        angle[k + 1] = angle[k] + std::acos(std::clamp(glm::dot(direction[k], direction[(k + 1) % d]), -1.0, 1.0));
    std::vector<glm::dvec2>& q = scratch.q;
    q.resize(d);
    for (std::size_t k = 0; k < d; ++k) {
        const double phi = angle[k] * 2.0 * std::numbers::pi / angle[d];
        q[k] = length[k] * glm::dvec2(std::cos(phi), std::sin(phi));
    }
    // For each neighbour l, the ring edge (r, r + 1) that the ray from q_l through the origin
    // crosses: the origin lies in triangle (q_l, q_r, q_r+1).
    std::vector<double>& lambda = scratch.lambda;
    lambda.assign(d, 0.0);
    std::size_t found = 0;
    for (std::size_t l = 0; l < d; ++l) {
        // The ray leaves the ring about opposite q_l: try the edges from there outward (one or two
        // tries instead of d / 2 on average).
        for (std::size_t j = 0; j < d; ++j) {
            const std::size_t r = (l + d + d / 2 - 1 + (j % 2 ? (j + 1) / 2 : d - j / 2)) % d;
            const std::size_t s = (r + 1) % d;
            if (r == l || s == l) continue;
            const double area = cross2(q[r] - q[l], q[s] - q[l]);
            if (area <= 0.0) continue;
            const double nl = cross2(q[r], q[s]);  // area times the origin's coordinate of q_l
            const double nr = cross2(q[s], q[l]);  // of q_r
            const double ns = cross2(q[l], q[r]);  // of q_s
            // A ray through a ring vertex touches two triangles: take the first tried (both give
            // the same coordinates, the third being 0).
            const double tolerance = -1e-12 * area;
            if (nl < tolerance || nr < tolerance || ns < tolerance) continue;
            lambda[l] += std::max(nl / area, 0.0), lambda[r] += std::max(nr / area, 0.0);
            lambda[s] += std::max(ns / area, 0.0);
            ++found;
            break;
        }
    }
    double sum = 0.0;
    for (double x : lambda) sum += x;
    // A scaled angle of pi or more leaves some neighbour without a triangle holding the vertex
    // (the flattened star is not star-shaped): chord-length weights for this vertex instead.
    std::size_t fell = 0;
    if (found < d) {
        fell = 1;
        sum = 0.0;
        for (std::size_t k = 0; k < d; ++k) sum += lambda[k] = 1.0 / length[k];
    }
    if (!(sum > 0.0)) throw geo::InputError("vertex " + std::to_string(v) + ": its one-ring flattens to nothing");
    const auto nb = adj.neighbors(v);
    for (std::size_t k = 0; k < d; ++k) {
        const auto it = std::lower_bound(nb.begin(), nb.end(), ring[k]);
        slot[adj.vertex_vertex_offsets[v] + std::size_t(it - nb.begin())] = lambda[k] / sum;
    }
    return fell;
}

}  // namespace

std::vector<double> floater_weights(const geo::Mesh& mesh, const geo::MeshAdjacency& adj, std::size_t* fallbacks) {
    return floater_weights(mesh, adj, adj.interior_vertices(), fallbacks);
}

std::vector<double> floater_weights(const geo::Mesh& mesh, const geo::MeshAdjacency& adj,
                                    const std::vector<std::uint8_t>& interior, std::size_t* fallbacks) {
    std::vector<double> slot(adj.vertex_vertices.size(), 0.0);
    // Each vertex writes only its own row: chunks of vertices on every core. Errors are kept per
    // chunk and the first chunk's is thrown, so the message does not depend on the threads.
    constexpr std::size_t kGrain = 512;
    const std::size_t chunks = geo::chunk_count(mesh.vertex_count(), kGrain);
    std::vector<std::size_t> fell(chunks, 0);
    std::vector<std::string> error(chunks);
    geo::parallel_for_chunks(mesh.vertex_count(), kGrain, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
        RowScratch scratch;
        try {
            for (std::size_t v = begin; v < end; ++v)
                if (interior[v]) fell[chunk] += floater_row(mesh, adj, std::uint32_t(v), slot, scratch);
        } catch (const geo::InputError& e) {
            error[chunk] = e.what();
        }
    });
    for (const std::string& e : error)
        if (!e.empty()) throw geo::InputError(e);
    if (fallbacks)
        for (std::size_t f : fell) *fallbacks += f;
    return slot;
}

}  // namespace gimg::passes

// Building the progressive mesh: quadric-ordered halfedge collapses that keep the mesh a closed
// genus-0 manifold (see progressive_mesh.h for the rules and why halfedge collapses).
#include "gimg/geometry/progressive_mesh.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <queue>

namespace gimg::geo {

namespace {

// Garland-Heckbert plane quadric: error(p) = p^T A p + 2 b.p + c, A symmetric, kept as 10 numbers.
struct Quadric {
    std::array<double, 10> q{};  // a00 a01 a02 a11 a12 a22 b0 b1 b2 c

    static Quadric of_plane(const glm::dvec3& n, double d, double weight) {
        Quadric r;
        r.q = {n.x * n.x, n.x * n.y, n.x * n.z, n.y * n.y, n.y * n.z, n.z * n.z, n.x * d, n.y * d, n.z * d, d * d};
        for (double& v : r.q) v *= weight;
        return r;
    }
    Quadric& operator+=(const Quadric& o) {
        for (std::size_t i = 0; i < q.size(); ++i) q[i] += o.q[i];
        return *this;
    }
    double error(const glm::dvec3& p) const {
        const double quad = q[0] * p.x * p.x + 2 * q[1] * p.x * p.y + 2 * q[2] * p.x * p.z + q[3] * p.y * p.y +
                            2 * q[4] * p.y * p.z + q[5] * p.z * p.z;
        return std::max(0.0, quad + 2 * (q[6] * p.x + q[7] * p.y + q[8] * p.z) + q[9]);
    }
};

// 1 for an equilateral triangle, falling to 0 as it degenerates: 4 sqrt(3) area / sum of squared edges.
double triangle_quality(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const double edges = glm::dot(b - a, b - a) + glm::dot(c - b, c - b) + glm::dot(a - c, a - c);
    if (!(edges > 0.0)) return 0.0;
    return 2.0 * std::sqrt(3.0) * glm::length(glm::cross(b - a, c - a)) / edges;
}

// New triangles must not fall below this quality unless the triangle they replace already did:
// thin triangles make huge cotangent weights on the coarse levels.
constexpr double kMinQuality = 0.05;

// 16 bytes: the heap holds a million of them on a 100K-vertex mesh and its sifting is much of
// the build's time (armadillo_loop1: 1.08 s with two version numbers in each entry, 0.87 s
// without). An entry is current while its cost is what the quadrics give now (they change only
// by collapses, which push the new costs); an outdated entry with the very same cost is the same
// candidate, so the collapses come in the same order as with version numbers.
struct Candidate {
    double cost;
    std::uint32_t from, to;  // collapse `from` into `to`
    // std::priority_queue pops the largest: make the cheapest (then the smallest ids) the largest.
    bool operator<(const Candidate& o) const {
        if (cost != o.cost) return cost > o.cost;
        if (from != o.from) return from > o.from;
        return to > o.to;
    }
};

class Collapser {
public:
    explicit Collapser(const geo::Mesh& mesh)
        : mesh_(mesh), tri_(mesh.triangles), vfaces_(mesh.vertex_count()), quadric_(mesh.vertex_count()),
          removed_(mesh.vertex_count(), 0), mark_(mesh.vertex_count(), 0), active_(mesh.vertex_count()) {
        for (std::uint32_t f = 0; f < tri_.size(); ++f) {
            const glm::uvec3 t = tri_[f];
            const glm::dvec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
            const glm::dvec3 cross = glm::cross(b - a, c - a);
            const double twice_area = glm::length(cross);
            if (twice_area > 0.0) {
                const glm::dvec3 n = cross / twice_area;
                const Quadric q = Quadric::of_plane(n, -glm::dot(n, a), 0.5 * twice_area);
                for (int k = 0; k < 3; ++k) quadric_[t[k]] += q;
            }
            for (int k = 0; k < 3; ++k) vfaces_[t[k]].push_back(f);
        }
    }

    std::size_t active() const { return active_; }

    // Collapses cheapest first until `target` vertices remain or no collapse passes the checks.
    // Candidates refused once are dropped; when the queue runs dry the queue is refilled from every
    // edge, because a refused collapse may pass after its neighbourhood changed.
    void run(std::size_t target, bool geometric) {
        while (active_ > target) {
            refill();
            bool progressed = false;
            while (active_ > target && !heap_.empty()) {
                const Candidate c = heap_.top();
                heap_.pop();
                if (removed_[c.from] || removed_[c.to] || c.cost != cost(c.from, c.to)) continue;
                if (try_collapse(c.from, c.to, geometric)) progressed = true;
            }
            if (!progressed) break;
        }
    }

    ProgressiveMesh finish(std::size_t base_vertex_count) {
        ProgressiveMesh pm;
        pm.vertex_count = mesh_.vertex_count();
        pm.triangles = mesh_.triangles;
        for (std::uint32_t v = 0; v < removed_.size(); ++v)
            if (!removed_[v]) pm.coarsest_vertices.push_back(v);
        pm.splits.assign(record_.rbegin(), record_.rend());
        pm.moved_faces = std::move(moved_);
        pm.base_vertex_count = base_vertex_count;
        return pm;
    }

private:
    void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) {
        out.clear();
        ++stamp_;
        for (std::uint32_t f : vfaces_[v])
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t n = tri_[f][k];
                if (n != v && mark_[n] != stamp_) {
                    mark_[n] = stamp_;
                    out.push_back(n);
                }
            }
    }

    double cost(std::uint32_t from, std::uint32_t to) const {
        Quadric q = quadric_[from];
        q += quadric_[to];
        return q.error(mesh_.positions[to]);
    }

    void push(std::uint32_t from, std::uint32_t to) { heap_.push({cost(from, to), from, to}); }

    void refill() {
        heap_ = {};
        std::vector<std::uint32_t> ring;
        for (std::uint32_t v = 0; v < removed_.size(); ++v) {
            if (removed_[v]) continue;
            neighbours(v, ring);
            for (std::uint32_t n : ring) push(n, v);  // every edge both ways, once from each end
        }
    }

    // The face's corners with `from` replaced by `to`.
    glm::uvec3 moved(glm::uvec3 t, std::uint32_t from, std::uint32_t to) const {
        for (int k = 0; k < 3; ++k)
            if (t[k] == from) t[k] = to;
        return t;
    }

    bool geometry_ok(std::uint32_t u, std::uint32_t k) const {
        const auto& p = mesh_.positions;
        for (std::uint32_t f : vfaces_[u]) {
            const glm::uvec3 t = tri_[f];
            if (t.x == k || t.y == k || t.z == k) continue;  // disappears with the collapse
            const glm::uvec3 n = moved(t, u, k);
            const glm::dvec3 before = glm::cross(p[t.y] - p[t.x], p[t.z] - p[t.x]);
            const glm::dvec3 after = glm::cross(p[n.y] - p[n.x], p[n.z] - p[n.x]);
            if (!(glm::dot(before, after) > 0.0)) return false;  // flips (or degenerates)
            const double q_after = triangle_quality(p[n.x], p[n.y], p[n.z]);
            if (q_after < std::min(kMinQuality, triangle_quality(p[t.x], p[t.y], p[t.z]))) return false;
        }
        return true;
    }

    bool try_collapse(std::uint32_t u, std::uint32_t k, bool geometric) {
        if (active_ <= 4) return false;
        // The two faces on the edge: (u, k, left) and (k, u, right) in counter-clockwise order.
        std::uint32_t born[2] = {0, 0}, left = 0, right = 0;
        int found_left = 0, found_right = 0;
        for (std::uint32_t f : vfaces_[u]) {
            const glm::uvec3 t = tri_[f];
            for (int c = 0; c < 3; ++c) {
                if (t[c] != u) continue;
                if (t[(c + 1) % 3] == k) born[0] = f, left = t[(c + 2) % 3], ++found_left;
                if (t[(c + 2) % 3] == k) born[1] = f, right = t[(c + 1) % 3], ++found_right;
            }
        }
        if (found_left != 1 || found_right != 1 || left == right) return false;
        // Link condition: the only common neighbours are left and right.
        neighbours(u, ring_u_);
        neighbours(k, ring_k_);
        ++stamp_;
        for (std::uint32_t n : ring_u_) mark_[n] = stamp_;
        int common = 0;
        for (std::uint32_t n : ring_k_) common += mark_[n] == stamp_;
        if (common != 2) return false;
        if (vfaces_[left].size() < 4 || vfaces_[right].size() < 4) return false;
        if (geometric && !geometry_ok(u, k)) return false;

        VertexSplit s;
        s.vertex = u;
        s.parent = k;
        s.left = left;
        s.right = right;
        for (int i = 0; i < 2; ++i) {
            s.born_faces[i] = born[i];
            s.born_triangles[i] = tri_[born[i]];
            for (int c = 0; c < 3; ++c) {
                auto& list = vfaces_[tri_[born[i]][c]];
                list.erase(std::find(list.begin(), list.end(), born[i]));
            }
        }
        s.moved_begin = std::uint32_t(moved_.size());
        for (std::uint32_t f : vfaces_[u]) {
            tri_[f] = moved(tri_[f], u, k);
            vfaces_[k].push_back(f);
            moved_.push_back(f);
        }
        s.moved_end = std::uint32_t(moved_.size());
        vfaces_[u].clear();
        removed_[u] = 1;
        --active_;
        quadric_[k] += quadric_[u];
        record_.push_back(s);
        neighbours(k, ring_k_);
        for (std::uint32_t n : ring_k_) {
            push(n, k);
            push(k, n);
        }
        return true;
    }

    const geo::Mesh& mesh_;
    std::vector<glm::uvec3> tri_;                     // current corners of every face
    std::vector<std::vector<std::uint32_t>> vfaces_;  // live faces around each vertex
    std::vector<Quadric> quadric_;
    std::vector<std::uint8_t> removed_;
    std::vector<std::uint32_t> mark_;
    std::uint32_t stamp_ = 0;
    std::vector<std::uint32_t> ring_u_, ring_k_;
    std::priority_queue<Candidate> heap_;
    std::size_t active_;
    std::vector<VertexSplit> record_;  // in collapse order
    std::vector<std::uint32_t> moved_;
};

}  // namespace

ProgressiveMesh build_progressive_mesh(const geo::Mesh& mesh, std::size_t base_vertices) {
    Collapser collapser(mesh);
    collapser.run(std::max<std::size_t>(base_vertices, 4), true);
    const std::size_t base = collapser.active();
    collapser.run(4, false);
    return collapser.finish(base);
}

}  // namespace gimg::geo

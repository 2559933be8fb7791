// The MAPS hierarchy (sec. 2.2-2.3): levels of maximal independent sets removed in increasing
// priority, each hole re-triangulated in the removed vertex's z^a flattening, every original vertex
// carried along as (triangle, barycentric) through the three tracking cases.
#include "gimg/geometry/error.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/maps.h"
#include "maps/ring_flattening.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

namespace gimg::passes {

namespace {

constexpr std::uint32_t kAlive = 0xffffffffu;

void check_input(const geo::Mesh& mesh, std::uint32_t& genus) {
    const geo::MeshInfo info = geo::analyze_topology(mesh);
    auto refuse = [](const std::string& why) { throw geo::InputError("MAPS needs a closed 2-manifold: " + why); };
    if (mesh.face_count() == 0) refuse("the mesh has no faces");
    if (info.nonfinite_vertices)
        refuse(std::to_string(info.nonfinite_vertices) + " vertices have NaN or infinite coordinates");
    if (!info.closed)
        refuse(info.boundary_loops == 1
                   ? std::string("the mesh has a boundary loop (a hole)")
                   : "the mesh has " + std::to_string(info.boundary_loops) + " boundary loops (holes)");
    if (!info.manifold) refuse("the mesh has non-manifold edges or vertices (gimg repair opens them)");
    if (!info.oriented) refuse("the faces are not consistently oriented (gimg repair turns them)");
    if (info.collapsed_faces || info.duplicate_faces)
        refuse("the mesh has " + std::to_string(info.collapsed_faces + info.duplicate_faces) +
               " collapsed or duplicate faces (gimg repair removes them)");
    if (info.isolated_vertices)
        refuse(std::to_string(info.isolated_vertices) + " vertices belong to no face (gimg repair removes them)");
    genus = 0;
    for (const geo::ComponentInfo& c : info.component_info) genus += std::uint32_t(c.genus.value_or(0));
}

// The current level: faces by id (removed ones dead), and per vertex its faces.
class LevelMesh {
public:
    explicit LevelMesh(const geo::Mesh& mesh) : positions_(mesh.positions), faces(mesh.triangles) {
        alive.assign(faces.size(), 1);
        vertex_faces.resize(mesh.vertex_count());
        for (std::uint32_t f = 0; f < faces.size(); ++f)
            for (int k = 0; k < 3; ++k) vertex_faces[faces[f][k]].push_back(f);
    }

    bool ring(std::uint32_t v, Ring& r) const { return gather_ring(faces, vertex_faces[v], v, r); }

    bool has_edge(std::uint32_t a, std::uint32_t b) const {
        for (std::uint32_t f : vertex_faces[a])
            if (faces[f][0] == b || faces[f][1] == b || faces[f][2] == b) return true;
        return false;
    }

    bool has_face(std::uint32_t a, std::uint32_t b, std::uint32_t c) const {
        for (std::uint32_t f : vertex_faces[a]) {
            const glm::uvec3 t = faces[f];
            const bool hb = t[0] == b || t[1] == b || t[2] == b, hc = t[0] == c || t[1] == c || t[2] == c;
            if (hb && hc) return true;
        }
        return false;
    }

    const std::vector<glm::dvec3>& positions() const { return positions_; }

    const std::vector<glm::dvec3>& positions_;
    std::vector<glm::uvec3> faces;
    std::vector<std::uint8_t> alive;
    std::vector<std::vector<std::uint32_t>> vertex_faces;
};

// One-ring area and |k1| + |k2| (cotangent mean curvature, angle-defect Gauss curvature).
void ring_measures(const std::vector<glm::dvec3>& p, std::uint32_t v, const Ring& r, double& area, double& kappa) {
    const std::size_t n = r.ring.size();
    glm::dvec3 laplace(0.0);
    double angle_sum = 0.0;
    area = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const glm::dvec3 a = p[r.ring[k]], b = p[r.ring[(k + 1) % n]], o = p[v];
        area += 0.5 * glm::length(glm::cross(a - o, b - o));
        angle_sum += corner_angle(o, a, b);
        // Cotangents of the angles opposite edges (o, a) and (o, b) in triangle (o, a, b).
        auto cot = [](glm::dvec3 apex, glm::dvec3 x, glm::dvec3 y) {
            const glm::dvec3 u = x - apex, w = y - apex;
            const double s = glm::length(glm::cross(u, w));
            return s > 0.0 ? glm::dot(u, w) / s : 0.0;
        };
        laplace += cot(b, o, a) * (a - o) + cot(a, o, b) * (b - o);
    }
    if (!(area > 0.0)) {
        kappa = 0.0;
        return;
    }
    const double third = area / 3.0;
    const double h = 0.5 * glm::length(laplace / (2.0 * third));
    const double gauss = (2.0 * std::numbers::pi - angle_sum) / third;
    const double root = std::sqrt(std::max(h * h - gauss, 0.0));
    kappa = std::abs(h + root) + std::abs(h - root);
    if (!std::isfinite(kappa)) kappa = 0.0;
}

class Hierarchy {
public:
    Hierarchy(const geo::Mesh& mesh, const MapsOptions& options) : mesh_(mesh), options_(options), level_(mesh) {
        param_.assign(mesh.vertex_count(), SurfacePoint{kAlive, {1, 0, 0}});
        face_points_.resize(mesh.face_count());
        vertex_alive_.assign(mesh.vertex_count(), 1);
        alive_count_ = mesh.vertex_count();
    }

    BaseDomain run(std::uint32_t target) {
        BaseDomain out;
        while (alive_count_ > target) {
            const auto start = std::chrono::steady_clock::now();
            MapsLevel level;
            std::vector<std::uint32_t> removed = remove_level(target, level);
            level.vertices = std::uint32_t(alive_count_);
            level.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (level.removed == 0) break;
            if (options_.check_tracking) check_all();
            out.levels.push_back(level);
            out.removed_sets.push_back(std::move(removed));
            if (options_.keep_levels) {
                out.level_faces.emplace_back();
                for (std::size_t f = 0; f < level_.faces.size(); ++f)
                    if (level_.alive[f]) out.level_faces.back().push_back(level_.faces[f]);
            }
        }
        compact(out);
        return out;
    }

private:
    std::vector<std::uint32_t> remove_level(std::size_t target, MapsLevel& level) {
        const std::size_t n = mesh_.vertex_count();
        std::vector<Ring> rings(n);
        std::vector<double> area(n, 0.0), kappa(n, 0.0);
        std::vector<std::uint32_t> order;
        double max_area = 0.0, max_kappa = 0.0;
        for (std::uint32_t v = 0; v < n; ++v) {
            if (!vertex_alive_[v] || !level_.ring(v, rings[v])) continue;
            ring_measures(level_.positions(), v, rings[v], area[v], kappa[v]);
            max_area = std::max(max_area, area[v]);
            max_kappa = std::max(max_kappa, kappa[v]);
            order.push_back(v);
        }
        std::vector<double> w(n, 0.0);
        for (std::uint32_t v : order)
            w[v] = options_.lambda * (max_area > 0 ? area[v] / max_area : 0.0) +
                   (1.0 - options_.lambda) * (max_kappa > 0 ? kappa[v] / max_kappa : 0.0);
        std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return w[a] < w[b]; });
        std::vector<std::uint8_t> blocked(n, 0);
        std::vector<std::uint32_t> removed;
        for (std::uint32_t v : order) {
            if (alive_count_ <= target) break;
            if (blocked[v]) continue;
            ++level.candidates;
            // Rings of unblocked vertices are still those of the level's start: only the
            // neighbours of removed vertices changed, and they are blocked.
            if (rings[v].ring.size() > options_.max_valence || !try_remove(v, rings[v])) {
                ++level.skipped;
                continue;
            }
            for (std::uint32_t u : rings[v].ring) blocked[u] = 1;
            removed.push_back(v);
            ++level.removed;
        }
        return removed;
    }

    bool try_remove(std::uint32_t c, Ring& r) {
        const std::size_t k = r.ring.size();
        // Diagonals that exist elsewhere in the level would make an edge of four faces.
        std::vector<std::uint8_t> forbidden(k * k, 0);
        for (std::size_t i = 0; i < k; ++i)
            for (std::size_t j = i + 2; j < k; ++j)
                if ((j + 1) % k != i && level_.has_edge(r.ring[i], r.ring[j]))
                    forbidden[i * k + j] = forbidden[j * k + i] = 1;
        if (!flatten_ring(level_.positions(), c, r, options_.flattening == RingFlattening::Polar, options_.max_cone) ||
            !triangulate_ring(r, forbidden))
            return false;
        const auto& p = level_.positions();
        for (const glm::uvec3& t : r.triangles) {
            const glm::dvec3 a = p[r.ring[t[0]]], b = p[r.ring[t[1]]], d = p[r.ring[t[2]]];
            const double longest = std::max({glm::length(b - a), glm::length(d - b), glm::length(a - d)});
            if (!(glm::length(glm::cross(b - a, d - a)) > 1e-10 * longest * longest)) return false;
            for (int e = 0; e < 3; ++e) {
                const std::uint32_t i = t[e], j = t[(e + 1) % 3];
                const bool ring_edge = (i + 1) % k == j || (j + 1) % k == i;
                if (!ring_edge && level_.has_edge(r.ring[i], r.ring[j])) return false;
            }
        }
        if (k == 3 && level_.has_face(r.ring[0], r.ring[1], r.ring[2])) return false;
        commit(c, r);
        return true;
    }

    void commit(std::uint32_t c, const Ring& r) {
        const std::size_t k = r.ring.size();
        std::vector<std::uint32_t> points{c};
        std::vector<glm::dvec2> chart{glm::dvec2(0.0)};
        for (std::size_t i = 0; i < k; ++i) {
            const std::uint32_t f = r.faces[i];
            const glm::uvec3 t = level_.faces[f];
            for (std::uint32_t q : face_points_[f]) {
                // Case 3: the old triangle's barycentric coordinates carried into the chart.
                glm::dvec2 mu(0.0);
                for (int e = 0; e < 3; ++e)
                    if (t[e] == r.ring[i])
                        mu += param_[q].bary[e] * r.mu[i];
                    else if (t[e] == r.ring[(i + 1) % k])
                        mu += param_[q].bary[e] * r.mu[(i + 1) % k];
                points.push_back(q);
                chart.push_back(mu);
            }
            face_points_[f].clear();
            level_.alive[f] = 0;
        }
        std::vector<std::uint32_t> new_faces;
        for (const glm::uvec3& t : r.triangles) {
            new_faces.push_back(std::uint32_t(level_.faces.size()));
            level_.faces.push_back({r.ring[t[0]], r.ring[t[1]], r.ring[t[2]]});
            level_.alive.push_back(1);
            face_points_.emplace_back();
        }
        // Cases 2 and 3: each point located among the new triangles of the chart.
        for (std::size_t i = 0; i < points.size(); ++i) {
            const Location l = locate(r, chart[i]);
            const std::uint32_t f = new_faces[l.triangle];
            param_[points[i]] = {f, l.bary};
            face_points_[f].push_back(points[i]);
            if (options_.check_tracking) check_point(points[i]);
        }
        for (std::uint32_t u : r.ring) {
            auto& fs = level_.vertex_faces[u];
            std::erase_if(fs, [&](std::uint32_t f) { return !level_.alive[f]; });
        }
        for (std::uint32_t f : new_faces)
            for (int e = 0; e < 3; ++e) level_.vertex_faces[level_.faces[f][e]].push_back(f);
        level_.vertex_faces[c].clear();
        vertex_alive_[c] = 0;
        --alive_count_;
    }

    void check_point(std::uint32_t q) const {
        const SurfacePoint& s = param_[q];
        if (s.face == kAlive) {
            if (!vertex_alive_[q]) throw std::logic_error("MAPS tracking: a removed vertex has no triangle");
            return;
        }
        if (s.face >= level_.faces.size() || !level_.alive[s.face])
            throw std::logic_error("MAPS tracking: a vertex lies in a triangle of no level");
        const double sum = s.bary.x + s.bary.y + s.bary.z;
        if (std::min({s.bary.x, s.bary.y, s.bary.z}) < -1e-10 || std::abs(sum - 1.0) > 1e-10)
            throw std::logic_error("MAPS tracking: barycentric coordinates outside the triangle");
    }

    void check_all() const {
        for (std::uint32_t q = 0; q < param_.size(); ++q) check_point(q);
    }

    void compact(BaseDomain& out) const {
        std::vector<std::uint32_t> vertex_id(mesh_.vertex_count(), kAlive), face_id(level_.faces.size(), kAlive);
        for (std::uint32_t v = 0; v < mesh_.vertex_count(); ++v)
            if (vertex_alive_[v]) {
                vertex_id[v] = std::uint32_t(out.original.size());
                out.original.push_back(v);
                out.base.positions.push_back(mesh_.positions[v]);
            }
        for (std::uint32_t f = 0; f < level_.faces.size(); ++f)
            if (level_.alive[f]) {
                face_id[f] = std::uint32_t(out.base.triangles.size());
                const glm::uvec3 t = level_.faces[f];
                out.base.triangles.push_back({vertex_id[t[0]], vertex_id[t[1]], vertex_id[t[2]]});
            }
        out.param.resize(mesh_.vertex_count());
        for (std::uint32_t v = 0; v < mesh_.vertex_count(); ++v) {
            if (param_[v].face != kAlive) {
                out.param[v] = {face_id[param_[v].face], param_[v].bary};
                continue;
            }
            // A base vertex: the corner of one of its base faces.
            const std::uint32_t f = level_.vertex_faces[v].front();
            const glm::uvec3 t = level_.faces[f];
            out.param[v] = {face_id[f], glm::dvec3(t[0] == v, t[1] == v, t[2] == v)};
        }
    }

    const geo::Mesh& mesh_;
    MapsOptions options_;
    LevelMesh level_;
    std::vector<SurfacePoint> param_;                      // kAlive faces: still a vertex of the level
    std::vector<std::vector<std::uint32_t>> face_points_;  // per face id: the removed vertices it holds
    std::vector<std::uint8_t> vertex_alive_;
    std::size_t alive_count_ = 0;
};

}  // namespace

BaseDomain build_base_domain(const geo::Mesh& mesh, const MapsOptions& options) {
    std::uint32_t genus = 0;
    check_input(mesh, genus);
    if (!(options.lambda >= 0.0 && options.lambda <= 1.0)) throw geo::InputError("lambda must lie in [0, 1]");
    if (options.max_valence < 3) throw geo::InputError("the valence cap must be at least 3");
    if (!(options.max_cone == 0.0 || options.max_cone >= 1.0))
        throw geo::InputError("the cone limit must be 0 (none) or at least 1");
    // About one base vertex per 20 of the mesh's, so base triangles shrink with its detail (cow's
    // horns and legs straddle base edges at 50), kept within 50 (1 + g) and 150 (1 + g).
    const std::uint32_t target = options.base_vertices ? options.base_vertices
                                                       : std::clamp(std::uint32_t(mesh.vertex_count() / 20),
                                                                    50u * (1u + genus), 150u * (1u + genus));
    Hierarchy h(mesh, options);
    return h.run(target);
}

}  // namespace gimg::passes

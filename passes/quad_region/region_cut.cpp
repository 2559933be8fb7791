// The region of four corners (sec. 4.1): each side traced face by face along its plane section,
// crossings close to a vertex merged into it, the faces it crosses split along it, and the faces on
// the left of W1 -> W2 -> W3 -> W4 gathered by a flood fill that the sides stop.
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/quad_region.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <map>
#include <set>
#include <string>

namespace gimg::passes {

namespace {

constexpr std::uint32_t kNone = 0xffffffffu;
constexpr double kMergeT = 0.05;  // a crossing within 5 % of an edge's end takes the vertex (the spec's choice)

struct Segment {
    std::uint32_t face, from, to;  // point ids: vertices, then inserted points from V on
};

class RegionCutter {
public:
    RegionCutter(const geo::Mesh& mesh, const std::array<std::uint32_t, 4>& corners)
        : mesh_(mesh), adj_(geo::build_adjacency(mesh)), corners_(corners), positions_(mesh.positions) {}

    QuadRegion cut() {
        const std::vector<glm::dvec3> face_n = geo::face_normals(mesh_);
        std::array<glm::dvec3, 4> normal{};
        for (int i = 0; i < 4; ++i) {
            for (std::uint32_t f : adj_.faces_of_vertex(corners_[i])) normal[i] += face_n[f];
            if (glm::length(normal[i]) == 0.0)
                throw geo::InputError("corner " + std::to_string(corners_[i]) + " has no face with a normal");
            normal[i] = glm::normalize(normal[i]);
        }
        std::array<std::vector<std::uint32_t>, 4> paths;
        for (int i = 0; i < 4; ++i) paths[i] = trace(i, normal[i], normal[(i + 1) % 4]);
        check_simple(paths);
        return gather(paths);
    }

private:
    glm::dvec3 pos(std::uint32_t id) const { return positions_[id]; }

    // The point where the plane crosses edge (a, b) at parameter t from a, or the nearer vertex.
    std::uint32_t crossing(std::uint32_t a, std::uint32_t b, double t) {
        if (t < kMergeT) return ++merged_, a;
        if (t > 1.0 - kMergeT) return ++merged_, b;
        const std::uint32_t e = adj_.find_edge(a, b);
        const bool forward = adj_.edges[2 * e] == a;
        const double te = forward ? t : 1.0 - t;  // from the edge's first vertex
        auto [it, fresh] = inserted_.try_emplace({e, te}, std::uint32_t(positions_.size()));
        if (fresh) {
            positions_.push_back(mesh_.positions[adj_.edges[2 * e]] * (1.0 - te) +
                                 mesh_.positions[adj_.edges[2 * e + 1]] * te);
            point_edge_.push_back(e);
        }
        return it->second;
    }

    bool is_vertex(std::uint32_t id) const { return id < mesh_.vertex_count(); }

    std::vector<std::uint32_t> trace(int i, const glm::dvec3& ni, const glm::dvec3& nj) {
        const std::uint32_t from = corners_[i], target = corners_[(i + 1) % 4];
        const glm::dvec3 w = mesh_.positions[from], toward = mesh_.positions[target] - w;
        glm::dvec3 n = glm::cross(w - mesh_.positions[target], ni + nj);
        if (glm::length(n) == 0.0)
            throw geo::InputError("side " + std::to_string(i + 1) + ": the corners' normals lie along the side");
        n = glm::normalize(n);
        const double on_plane = 1e-12 * mesh_.bounds().diagonal();
        auto d = [&](std::uint32_t v) { return glm::dot(n, mesh_.positions[v] - w); };
        std::vector<std::uint32_t> path{from};
        std::set<std::uint32_t> visited;
        std::uint32_t came = kNone;  // the face the current edge point was reached through
        const std::string side =
            "side " + std::to_string(i + 1) + " (" + std::to_string(from) + " -> " + std::to_string(target) + ")";
        for (std::size_t step = 0; path.back() != target; ++step) {
            if (step > mesh_.face_count() + 4) throw geo::InputError(side + " does not reach its end corner");
            const std::uint32_t cur = path.back();
            std::uint32_t next = kNone, face = kNone;
            if (is_vertex(cur)) {
                double best = -1e300;
                struct Choice {
                    std::uint32_t a = kNone, b = kNone;
                    double t = -1.0;
                } chosen;
                for (std::uint32_t f : adj_.faces_of_vertex(cur)) {
                    if (visited.count(f)) continue;
                    const glm::uvec3& t = mesh_.triangles[f];
                    const int k = t[0] == cur ? 0 : t[1] == cur ? 1 : 2;
                    const std::uint32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
                    // Candidates: a vertex on the plane, or the crossing of the opposite edge (made a
                    // point only once chosen).
                    std::vector<std::pair<std::uint32_t, double>> cands;  // (vertex, -1) or (a, t on a -> b)
                    for (std::uint32_t v : {a, b})
                        if (v == target || std::abs(d(v)) <= on_plane) cands.emplace_back(v, -1.0);
                    const double da = d(a), db = d(b);
                    if ((da > on_plane && db < -on_plane) || (da < -on_plane && db > on_plane))
                        cands.emplace_back(a, da / (da - db));
                    for (const auto& [v, t_ab] : cands) {
                        const std::uint32_t q = t_ab < 0.0 ? v : t_ab < kMergeT ? a : t_ab > 1.0 - kMergeT ? b : kNone;
                        if (q == cur ||
                            (q != kNone && q != target && std::find(path.begin(), path.end(), q) != path.end()))
                            continue;
                        const glm::dvec3 at =
                            t_ab < 0.0 ? pos(v) : mesh_.positions[a] * (1.0 - t_ab) + mesh_.positions[b] * t_ab;
                        const double score = q == target ? 1e300 : glm::dot(at - pos(cur), toward);
                        if (score > best)
                            best = score, face = f, chosen = {t_ab < 0.0 ? v : a, t_ab < 0.0 ? kNone : b, t_ab};
                    }
                }
                if (face != kNone) next = chosen.t < 0.0 ? chosen.a : crossing(chosen.a, chosen.b, chosen.t);
                if (next == kNone || (path.size() == 1 && best <= 0.0))
                    throw geo::InputError(side + " leaves the mesh before it reaches its end corner");
            } else {
                const std::uint32_t e = point_edge_[cur - mesh_.vertex_count()];
                for (std::uint32_t f : adj_.faces_of_edge(e))
                    if (f != came && !visited.count(f)) face = f;
                if (face == kNone) throw geo::InputError(side + " runs off the mesh's boundary");
                const glm::uvec3& t = mesh_.triangles[face];
                const std::uint32_t a = adj_.edges[2 * e], b = adj_.edges[2 * e + 1];
                const std::uint32_t c = t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
                const double da = d(a), dc = d(c);
                if (c == target || std::abs(dc) <= on_plane) {
                    next = c;
                } else if ((da > 0.0) != (dc > 0.0)) {
                    next = crossing(a, c, da / (da - dc));
                } else {
                    const double db = d(b);
                    next = crossing(b, c, db / (db - dc));
                }
                if (next != target && std::find(path.begin(), path.end(), next) != path.end())
                    throw geo::InputError(side + " turns back on itself");
            }
            visited.insert(face);
            segments_.push_back({face, cur, next});
            came = face;
            path.push_back(next);
        }
        return path;
    }

    void check_simple(const std::array<std::vector<std::uint32_t>, 4>& paths) const {
        std::map<std::uint32_t, int> owner;
        for (int i = 0; i < 4; ++i)
            for (std::size_t k = 0; k + 1 < paths[i].size(); ++k) {
                const auto [it, fresh] = owner.emplace(paths[i][k], i);
                if (!fresh)
                    throw geo::InputError("sides " + std::to_string(it->second + 1) + " and " + std::to_string(i + 1) +
                                          " cross: choose other corners");
            }
    }

    // Splits every face a side crosses along it, then floods the faces on the sides' left.
    QuadRegion gather(const std::array<std::vector<std::uint32_t>, 4>& paths) {
        std::map<std::uint32_t, std::vector<std::pair<std::uint32_t, std::uint32_t>>> chords;
        std::set<std::pair<std::uint32_t, std::uint32_t>> barrier;
        for (const Segment& s : segments_) {
            chords[s.face].emplace_back(s.from, s.to);
            barrier.insert(std::minmax(s.from, s.to));
        }
        // Points on each edge, for the faces that hold them.
        std::map<std::uint32_t, std::vector<std::uint32_t>> on_edge;
        for (std::uint32_t p = 0; p < point_edge_.size(); ++p)
            on_edge[point_edge_[p]].push_back(std::uint32_t(mesh_.vertex_count()) + p);
        std::vector<glm::uvec3> triangles;
        for (std::uint32_t f = 0; f < mesh_.face_count(); ++f) {
            const glm::uvec3& t = mesh_.triangles[f];
            const bool touched = chords.count(f) || std::any_of(&adj_.face_edges[3 * f], &adj_.face_edges[3 * f] + 3,
                                                                [&](std::uint32_t e) { return on_edge.count(e); });
            if (!touched) {
                triangles.push_back(t);
                continue;
            }
            std::vector<std::uint32_t> polygon;
            for (int k = 0; k < 3; ++k) {
                polygon.push_back(t[k]);
                const std::uint32_t e = adj_.face_edges[3 * f + k];
                if (!on_edge.count(e)) continue;
                std::vector<std::uint32_t> pts = on_edge[e];
                const glm::dvec3 from = pos(t[k]);
                std::sort(pts.begin(), pts.end(), [&](std::uint32_t x, std::uint32_t y) {
                    return glm::distance(pos(x), from) < glm::distance(pos(y), from);
                });
                polygon.insert(polygon.end(), pts.begin(), pts.end());
            }
            split(polygon, chords.count(f) ? chords[f] : std::vector<std::pair<std::uint32_t, std::uint32_t>>{},
                  triangles);
        }
        // Flood over triangles joined by edges that are not on a side.
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> by_edge;
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> directed;
        for (std::uint32_t k = 0; k < triangles.size(); ++k)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t a = triangles[k][c], b = triangles[k][(c + 1) % 3];
                by_edge[std::minmax(a, b)].push_back(k);
                directed[{a, b}] = k;
            }
        const Segment& first = segments_.front();
        const auto seed = directed.find({first.from, first.to});
        if (seed == directed.end()) throw geo::InputError("side 1 has no face on its left");
        std::vector<std::uint8_t> in(triangles.size(), 0);
        std::vector<std::uint32_t> stack{seed->second};
        in[seed->second] = 1;
        while (!stack.empty()) {
            const std::uint32_t k = stack.back();
            stack.pop_back();
            for (int c = 0; c < 3; ++c) {
                const auto key = std::minmax(triangles[k][c], triangles[k][(c + 1) % 3]);
                if (barrier.count(key)) continue;
                for (std::uint32_t o : by_edge[key])
                    if (!in[o]) in[o] = 1, stack.push_back(o);
            }
        }
        for (const Segment& s : segments_) {
            const auto right = directed.find({s.to, s.from});
            if (right != directed.end() && in[right->second])
                throw geo::InputError(
                    "the sides do not separate a region: W1 -> W2 -> W3 -> W4 must enclose the "
                    "faces on its left (corners counter-clockwise seen from outside)");
        }
        // The region as its own mesh.
        QuadRegion r;
        std::vector<std::uint32_t> index(positions_.size(), kNone);
        for (std::uint32_t k = 0; k < triangles.size(); ++k) {
            if (!in[k]) continue;
            glm::uvec3 t;
            for (int c = 0; c < 3; ++c) {
                std::uint32_t& id = index[triangles[k][c]];
                if (id == kNone) {
                    id = std::uint32_t(r.mesh.positions.size());
                    r.mesh.positions.push_back(positions_[triangles[k][c]]);
                    r.original.push_back(is_vertex(triangles[k][c]) ? triangles[k][c] : kInsertedNode);
                }
                t[c] = id;
            }
            r.mesh.triangles.push_back(t);
        }
        std::vector<std::uint32_t> outer(positions_.size(), kNone);
        for (std::uint32_t k = 0; k < triangles.size(); ++k) {
            if (in[k]) continue;
            glm::uvec3 t;
            for (int c = 0; c < 3; ++c) {
                std::uint32_t& id = outer[triangles[k][c]];
                if (id == kNone)
                    id = std::uint32_t(r.outside.positions.size()),
                    r.outside.positions.push_back(positions_[triangles[k][c]]);
                t[c] = id;
            }
            r.outside.triangles.push_back(t);
        }
        r.side.assign(r.mesh.positions.size(), 0);
        for (int i = 0; i < 4; ++i)
            for (std::size_t k = 0; k + 1 < paths[i].size(); ++k) r.side[index[paths[i][k]]] = std::uint8_t(i + 1);
        for (int i = 0; i < 4; ++i) r.corners[i] = index[corners_[i]];
        r.merged = merged_;
        for (std::uint32_t id = std::uint32_t(mesh_.vertex_count()); id < positions_.size(); ++id)
            r.inserted += index[id] != kNone;
        try {
            check_disk_mesh(r.mesh);
        } catch (const geo::InputError& e) {
            throw geo::InputError(std::string("the region is not a disk (it may reach the mesh's boundary): ") +
                                  e.what());
        }
        return r;
    }

    // Cuts a convex polygon (a face with points on its edges) along its chords and triangulates the
    // pieces without flat triangles: a fan over the corners that turn, then each point on a straight
    // stretch splits the triangle that holds it.
    void split(const std::vector<std::uint32_t>& polygon, std::vector<std::pair<std::uint32_t, std::uint32_t>> chords,
               std::vector<glm::uvec3>& out) {
        const std::size_t n = polygon.size();
        for (std::size_t c = 0; c < chords.size(); ++c) {
            const auto ia = std::find(polygon.begin(), polygon.end(), chords[c].first) - polygon.begin();
            const auto ib = std::find(polygon.begin(), polygon.end(), chords[c].second) - polygon.begin();
            if (std::size_t(ia) == n || std::size_t(ib) == n) continue;  // not in this piece
            const std::size_t lo = std::size_t(std::min(ia, ib)), hi = std::size_t(std::max(ia, ib));
            if (hi - lo == 1 || (lo == 0 && hi == n - 1)) continue;  // along an edge of the piece
            std::vector<std::uint32_t> first(polygon.begin() + std::ptrdiff_t(lo),
                                             polygon.begin() + std::ptrdiff_t(hi) + 1);
            std::vector<std::uint32_t> second(polygon.begin() + std::ptrdiff_t(hi), polygon.end());
            second.insert(second.end(), polygon.begin(), polygon.begin() + std::ptrdiff_t(lo) + 1);
            chords.erase(chords.begin() + std::ptrdiff_t(c));
            split(first, chords, out);
            split(second, chords, out);
            return;
        }
        std::vector<std::uint8_t> turns(n, 0);
        for (std::size_t k = 0; k < n; ++k) {
            const glm::dvec3 a = pos(polygon[(k + n - 1) % n]), b = pos(polygon[k]), c = pos(polygon[(k + 1) % n]);
            turns[k] = glm::length(glm::cross(b - a, c - b)) > 1e-9 * glm::length(b - a) * glm::length(c - b);
        }
        std::vector<std::uint32_t> strict;
        for (std::size_t k = 0; k < n; ++k)
            if (turns[k]) strict.push_back(std::uint32_t(k));
        if (strict.size() < 3) return;  // a sliver with no area
        std::vector<glm::uvec3> tris;
        for (std::size_t k = 1; k + 1 < strict.size(); ++k)
            tris.push_back({polygon[strict[0]], polygon[strict[k]], polygon[strict[k + 1]]});
        for (std::size_t s = 0; s < strict.size(); ++s) {
            const std::uint32_t x = polygon[strict[s]], y = polygon[strict[(s + 1) % strict.size()]];
            std::vector<std::uint32_t> between;
            for (std::size_t k = (strict[s] + 1) % n; k != strict[(s + 1) % strict.size()]; k = (k + 1) % n)
                between.push_back(polygon[k]);
            if (between.empty()) continue;
            for (std::size_t k = 0; k < tris.size(); ++k) {
                int at = -1;
                for (int c = 0; c < 3; ++c)
                    if (tris[k][c] == x && tris[k][(c + 1) % 3] == y) at = c;
                if (at < 0) continue;
                const std::uint32_t z = tris[k][(at + 2) % 3];
                std::vector<std::uint32_t> chain{x};
                chain.insert(chain.end(), between.begin(), between.end());
                chain.push_back(y);
                tris.erase(tris.begin() + std::ptrdiff_t(k));
                for (std::size_t c = 0; c + 1 < chain.size(); ++c) tris.push_back({chain[c], chain[c + 1], z});
                break;
            }
        }
        out.insert(out.end(), tris.begin(), tris.end());
    }

    const geo::Mesh& mesh_;
    geo::MeshAdjacency adj_;
    std::array<std::uint32_t, 4> corners_;
    std::vector<glm::dvec3> positions_;      // the mesh's vertices, then the inserted points
    std::vector<std::uint32_t> point_edge_;  // per inserted point, its edge
    std::map<std::pair<std::uint32_t, double>, std::uint32_t> inserted_;
    std::vector<Segment> segments_;
    std::size_t merged_ = 0;
};

}  // namespace

QuadRegion cut_quad_region(const geo::Mesh& mesh, const std::array<std::uint32_t, 4>& corners) {
    for (int i = 0; i < 4; ++i) {
        if (corners[i] >= mesh.vertex_count())
            throw geo::InputError("corner " + std::to_string(corners[i]) + " is not a vertex of the mesh (it has " +
                                  std::to_string(mesh.vertex_count()) + ")");
        for (int j = 0; j < i; ++j)
            if (corners[i] == corners[j]) throw geo::InputError("the four corners must be distinct vertices");
    }
    return RegionCutter(mesh, corners).cut();
}

}  // namespace gimg::passes

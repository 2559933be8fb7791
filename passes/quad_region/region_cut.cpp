// The region of four (or three) corners (sec. 4.1): each side traced face by face along its plane
// section, crossings close to a vertex merged into it, the faces it crosses split along it, and the
// faces on the left of W1 -> W2 -> W3 (-> W4) gathered by a flood fill that the sides stop.
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/quad_region.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace gimg::passes {

namespace {

constexpr std::uint32_t kNone = 0xffffffffu;
// face_across: an edge whose faces are not one pair facing each other (a non-manifold edge, or
// neighbours of opposite orientation), looked up the general way.
constexpr std::uint32_t kAcrossUnknown = 0xfffffffeu;

// Per face and edge slot c (corner c to corner c + 1): the other face of that edge, which holds it
// the other way round; kNone on the boundary; kAcrossUnknown where it is not that simple. The
// flood through the untouched faces reads one entry instead of the edge's faces and their corners.
std::vector<std::uint32_t> face_across(const geo::Mesh& mesh, const geo::MeshAdjacency& adj) {
    std::vector<std::uint32_t> across(3 * mesh.face_count(), kNone);
    auto slot = [&](std::uint32_t f, std::uint32_t e) {
        int c = 0;
        while (c < 2 && adj.face_edges[3 * std::size_t(f) + c] != e) ++c;
        return 3 * std::size_t(f) + c;
    };
    for (std::size_t i = 0; i < across.size(); ++i)
        if (adj.face_edges[i] == geo::kInvalidIndex) across[i] = kAcrossUnknown;
    for (std::uint32_t e = 0; e < adj.edge_count(); ++e) {
        const auto faces = adj.faces_of_edge(e);
        if (faces.size() < 2) continue;
        if (faces.size() > 2) {
            for (std::uint32_t f : faces) across[slot(f, e)] = kAcrossUnknown;
            continue;
        }
        const std::size_t sf = slot(faces[0], e), sg = slot(faces[1], e);
        const glm::uvec3 &tf = mesh.triangles[faces[0]], &tg = mesh.triangles[faces[1]];
        const int cf = int(sf % 3), cg = int(sg % 3);
        const bool opposed = faces[0] != faces[1] && tf[cf] == tg[(cg + 1) % 3] && tf[(cf + 1) % 3] == tg[cg];
        across[sf] = opposed ? faces[1] : kAcrossUnknown;
        across[sg] = opposed ? faces[0] : kAcrossUnknown;
    }
    return across;
}
constexpr double kMergeT = 0.05;  // a crossing within 5 % of an edge's end takes the vertex (the spec's choice)

struct Segment {
    std::uint32_t face, from, to;  // point ids: vertices, then inserted points from V on
};

class RegionCutter {
public:
    RegionCutter(const geo::Mesh& mesh, const geo::MeshAdjacency& adj, const std::vector<glm::dvec3>& face_normals,
                 const std::vector<std::uint32_t>& across, double diagonal, std::vector<std::uint32_t> corners,
                 bool with_outside)
        : mesh_(mesh), adj_(adj), face_n_(face_normals), across_(across), diagonal_(diagonal),
          corners_(std::move(corners)), n_(int(corners_.size())), with_outside_(with_outside) {}

    QuadRegion cut() {
        std::vector<glm::dvec3> normal(corners_.size(), glm::dvec3(0.0));
        for (int i = 0; i < n_; ++i) {
            for (std::uint32_t f : adj_.faces_of_vertex(corners_[i])) normal[i] += face_n_[f];
            if (glm::length(normal[i]) == 0.0)
                throw geo::InputError("corner " + std::to_string(corners_[i]) + " has no face with a normal");
            normal[i] = glm::normalize(normal[i]);
        }
        std::vector<std::vector<std::uint32_t>> paths(corners_.size());
        for (int i = 0; i < n_; ++i) {
            const std::size_t segments = segments_.size(), points = point_edge_.size();
            try {
                paths[i] = trace(i, normal[i], normal[(i + 1) % n_]);
            } catch (const geo::InputError&) {
                // The section left the mesh or turned back: the shortest edge path instead (sec. 4.1's
                // fallback), with the points the failed trace inserted taken back.
                segments_.resize(segments);
                for (auto it = inserted_.begin(); it != inserted_.end();)
                    it = it->second >= mesh_.vertex_count() + points ? inserted_.erase(it) : std::next(it);
                point_edge_.resize(points);
                point_pos_.resize(points);
                paths[i] = edge_path(i);
                ++fallbacks_;
            }
        }
        check_simple(paths);
        return gather(paths);
    }

private:
    glm::dvec3 pos(std::uint32_t id) const {
        return id < mesh_.vertex_count() ? mesh_.positions[id] : point_pos_[id - mesh_.vertex_count()];
    }

    // The point where the plane crosses edge (a, b) at parameter t from a, or the nearer vertex.
    std::uint32_t crossing(std::uint32_t a, std::uint32_t b, double t) {
        if (t < kMergeT) return ++merged_, a;
        if (t > 1.0 - kMergeT) return ++merged_, b;
        const std::uint32_t e = adj_.find_edge(a, b);
        const bool forward = adj_.edges[2 * e] == a;
        const double te = forward ? t : 1.0 - t;  // from the edge's first vertex
        auto [it, fresh] = inserted_.try_emplace({e, te}, std::uint32_t(mesh_.vertex_count() + point_pos_.size()));
        if (fresh) {
            point_pos_.push_back(mesh_.positions[adj_.edges[2 * e]] * (1.0 - te) +
                                 mesh_.positions[adj_.edges[2 * e + 1]] * te);
            point_edge_.push_back(e);
        }
        return it->second;
    }

    bool is_vertex(std::uint32_t id) const { return id < mesh_.vertex_count(); }

    // The shortest path along edges from corner i to corner i + 1 (Dijkstra, edge lengths).
    std::vector<std::uint32_t> edge_path(int i) {
        const std::uint32_t from = corners_[i], target = corners_[(i + 1) % n_];
        std::vector<double> dist(mesh_.vertex_count(), std::numeric_limits<double>::infinity());
        std::vector<std::uint32_t> parent(mesh_.vertex_count(), kNone);
        using Item = std::pair<double, std::uint32_t>;
        std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
        dist[from] = 0.0;
        queue.emplace(0.0, from);
        while (!queue.empty()) {
            const auto [d, v] = queue.top();
            queue.pop();
            if (v == target) break;
            if (d > dist[v]) continue;
            for (std::uint32_t w : adj_.neighbors(v)) {
                const double nd = d + glm::distance(mesh_.positions[v], mesh_.positions[w]);
                if (nd < dist[w]) dist[w] = nd, parent[w] = v, queue.emplace(nd, w);
            }
        }
        if (parent[target] == kNone)
            throw geo::InputError("side " + std::to_string(i + 1) + ": no path joins its corners");
        std::vector<std::uint32_t> path{target};
        while (path.back() != from) path.push_back(parent[path.back()]);
        std::reverse(path.begin(), path.end());
        for (std::size_t k = 0; k + 1 < path.size(); ++k) segments_.push_back({kNone, path[k], path[k + 1]});
        return path;
    }

    std::vector<std::uint32_t> trace(int i, const glm::dvec3& ni, const glm::dvec3& nj) {
        const std::uint32_t from = corners_[i], target = corners_[(i + 1) % n_];
        const glm::dvec3 w = mesh_.positions[from], toward = mesh_.positions[target] - w;
        glm::dvec3 n = glm::cross(w - mesh_.positions[target], ni + nj);
        if (glm::length(n) == 0.0)
            throw geo::InputError("side " + std::to_string(i + 1) + ": the corners' normals lie along the side");
        n = glm::normalize(n);
        const double on_plane = 1e-12 * diagonal_;
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

    void check_simple(const std::vector<std::vector<std::uint32_t>>& paths) const {
        std::map<std::uint32_t, int> owner;
        for (int i = 0; i < n_; ++i)
            for (std::size_t k = 0; k + 1 < paths[i].size(); ++k) {
                const auto [it, fresh] = owner.emplace(paths[i][k], i);
                if (!fresh)
                    throw geo::InputError("sides " + std::to_string(it->second + 1) + " and " + std::to_string(i + 1) +
                                          " cross: choose other corners");
            }
    }

    static std::uint64_t key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

    // Splits every face a side crosses along it, then floods the faces on the sides' left: original
    // faces through the mesh's adjacency, split faces through their pieces' edges, so the work grows
    // with the region, not the mesh.
    QuadRegion gather(const std::vector<std::vector<std::uint32_t>>& paths) {
        std::unordered_map<std::uint32_t, std::vector<std::pair<std::uint32_t, std::uint32_t>>> chords;
        std::unordered_set<std::uint64_t> barrier;                     // side segments through faces
        std::vector<std::uint8_t> barrier_edge(adj_.edge_count(), 0);  // side segments along mesh edges
        for (const Segment& sg : segments_) {
            if (sg.face != kNone) chords[sg.face].emplace_back(sg.from, sg.to);
            const std::uint32_t e = is_vertex(sg.from) && is_vertex(sg.to) ? adj_.find_edge(sg.from, sg.to) : kNone;
            if (e != kNone && e != geo::kInvalidIndex)
                barrier_edge[e] = 1;
            else
                barrier.insert(key(std::min(sg.from, sg.to), std::max(sg.from, sg.to)));
        }
        std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> on_edge;
        for (std::uint32_t p = 0; p < point_edge_.size(); ++p)
            on_edge[point_edge_[p]].push_back(std::uint32_t(mesh_.vertex_count()) + p);
        // Faces to split: those a side crosses and those with a point on an edge.
        std::vector<std::uint32_t> touched;
        for (const auto& [f, c] : chords) touched.push_back(f);
        for (const auto& [e, pts] : on_edge)
            for (std::uint32_t f : adj_.faces_of_edge(e)) touched.push_back(f);
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        std::vector<glm::uvec3> pieces;
        for (std::uint32_t f : touched) {
            const glm::uvec3& t = mesh_.triangles[f];
            std::vector<std::uint32_t> polygon;
            for (int k = 0; k < 3; ++k) {
                polygon.push_back(t[k]);
                const auto it = on_edge.find(adj_.face_edges[3 * f + k]);
                if (it == on_edge.end()) continue;
                std::vector<std::uint32_t> pts = it->second;
                const glm::dvec3 from = pos(t[k]);
                std::sort(pts.begin(), pts.end(), [&](std::uint32_t x, std::uint32_t y) {
                    return glm::distance(pos(x), from) < glm::distance(pos(y), from);
                });
                polygon.insert(polygon.end(), pts.begin(), pts.end());
            }
            const auto c = chords.find(f);
            split(polygon, c != chords.end() ? c->second : std::vector<std::pair<std::uint32_t, std::uint32_t>>{},
                  pieces);
        }
        const std::size_t nf = mesh_.face_count();
        std::vector<std::uint8_t> is_touched(nf, 0);
        for (std::uint32_t f : touched) is_touched[f] = 1;
        std::unordered_map<std::uint64_t, std::uint32_t> piece_by_edge;  // directed edge -> node
        for (std::uint32_t k = 0; k < pieces.size(); ++k)
            for (int c = 0; c < 3; ++c)
                piece_by_edge[key(pieces[k][c], pieces[k][(c + 1) % 3])] = std::uint32_t(nf) + k;
        auto triangle = [&](std::uint32_t node) { return node < nf ? mesh_.triangles[node] : pieces[node - nf]; };
        // The piece holding the directed edge a -> b, or kNone.
        auto piece = [&](std::uint32_t a, std::uint32_t b) {
            const auto it = piece_by_edge.find(key(a, b));
            return it != piece_by_edge.end() ? it->second : kNone;
        };
        // The node (untouched face or piece) holding the directed edge a -> b, or kNone.
        auto holding = [&](std::uint32_t a, std::uint32_t b) {
            if (const std::uint32_t p = piece(a, b); p != kNone) return p;
            if (!is_vertex(a) || !is_vertex(b)) return kNone;
            const std::uint32_t e = adj_.find_edge(a, b);
            if (e == geo::kInvalidIndex) return kNone;
            for (std::uint32_t g : adj_.faces_of_edge(e)) {
                if (is_touched[g]) continue;
                const glm::uvec3& t = mesh_.triangles[g];
                for (int c = 0; c < 3; ++c)
                    if (t[c] == a && t[(c + 1) % 3] == b) return g;
            }
            return kNone;
        };
        const Segment& first = segments_.front();
        const std::uint32_t seed = holding(first.from, first.to);
        if (seed == kNone) throw geo::InputError("side 1 has no face on its left");
        std::vector<std::uint8_t> in(nf + pieces.size(), 0);
        std::vector<std::uint32_t> region_nodes{seed}, stack{seed};
        in[seed] = 1;
        while (!stack.empty()) {
            const std::uint32_t node = stack.back();
            stack.pop_back();
            const glm::uvec3 t = triangle(node);
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t a = t[c], b = t[(c + 1) % 3];
                std::uint32_t o = kNone;
                if (node < nf) {  // an untouched face: its edges are mesh edges
                    const std::uint32_t e = adj_.face_edges[3 * node + c];
                    if (e == geo::kInvalidIndex || barrier_edge[e]) continue;
                    // As holding(b, a): a piece first (only a touched face's pieces can hold a mesh edge).
                    if (const std::uint32_t across = across_[3 * node + c]; across != kAcrossUnknown) {
                        if (across != kNone) o = is_touched[across] ? piece(b, a) : across;  // kNone: boundary
                    } else {
                        const auto faces = adj_.faces_of_edge(e);
                        if (std::any_of(faces.begin(), faces.end(),
                                        [&](std::uint32_t g) { return is_touched[g] != 0; }))
                            o = piece(b, a);
                        for (std::size_t i = 0; i < faces.size() && o == kNone; ++i) {
                            const std::uint32_t g = faces[i];
                            if (is_touched[g]) continue;
                            const glm::uvec3& u = mesh_.triangles[g];
                            for (int k = 0; k < 3 && o == kNone; ++k)
                                if (u[k] == b && u[(k + 1) % 3] == a) o = g;
                        }
                    }
                } else {
                    if (barrier.count(key(std::min(a, b), std::max(a, b)))) continue;
                    if (is_vertex(a) && is_vertex(b))
                        if (const std::uint32_t e = adj_.find_edge(a, b); e != geo::kInvalidIndex && barrier_edge[e])
                            continue;
                    o = holding(b, a);
                }
                if (o != kNone && !in[o]) in[o] = 1, stack.push_back(o), region_nodes.push_back(o);
            }
        }
        for (const Segment& sg : segments_) {
            const std::uint32_t right = holding(sg.to, sg.from);
            if (right != kNone && in[right])
                throw geo::InputError(
                    "the sides do not separate a region: W1 -> W2 -> W3 -> W4 must enclose the "
                    "faces on its left (corners counter-clockwise seen from outside)");
        }
        QuadRegion r;
        // Each vertex or inserted point's index in the region (kNone: not in it), a table rather
        // than a hash map: the region touches a few corners of each of its thousands of nodes.
        std::vector<std::uint32_t> index(mesh_.vertex_count() + point_pos_.size(), kNone);
        for (std::uint32_t node : region_nodes) {
            const glm::uvec3 t = triangle(node);
            glm::uvec3 out;
            for (int c = 0; c < 3; ++c) {
                std::uint32_t& id = index[t[c]];
                if (id == kNone) {
                    id = std::uint32_t(r.mesh.positions.size());
                    r.mesh.positions.push_back(pos(t[c]));
                    r.original.push_back(is_vertex(t[c]) ? t[c] : kInsertedNode);
                }
                out[c] = id;
            }
            r.mesh.triangles.push_back(out);
        }
        // The rest of the mesh, for pictures: untouched faces and pieces outside.
        std::vector<std::uint32_t> outer(with_outside_ ? mesh_.vertex_count() + point_pos_.size() : 0, kNone);
        for (std::uint32_t node = 0; with_outside_ && node < in.size(); ++node) {
            if (in[node] || (node < nf && is_touched[node])) continue;
            const glm::uvec3 t = triangle(node);
            glm::uvec3 out;
            for (int c = 0; c < 3; ++c) {
                std::uint32_t& id = outer[t[c]];
                if (id == kNone)
                    id = std::uint32_t(r.outside.positions.size()), r.outside.positions.push_back(pos(t[c]));
                out[c] = id;
            }
            r.outside.triangles.push_back(out);
        }
        const auto region_index = [&](std::uint32_t id) {
            if (index[id] == kNone)
                throw geo::InputError("the sides do not bound one region: a side point lies outside it");
            return index[id];
        };
        r.side.assign(r.mesh.positions.size(), 0);
        for (int i = 0; i < n_; ++i)
            for (std::size_t k = 0; k + 1 < paths[i].size(); ++k)
                r.side[region_index(paths[i][k])] = std::uint8_t(i + 1);
        r.corner_count = std::uint32_t(n_);
        for (int i = 0; i < n_; ++i) r.corners[i] = region_index(corners_[i]);
        r.merged = merged_;
        r.fallback_sides = fallbacks_;
        for (std::uint32_t p = 0; p < point_pos_.size(); ++p) r.inserted += index[mesh_.vertex_count() + p] != kNone;
        check_region_disk(r.mesh);
        return r;
    }

    // The region is a disk. Its faces are faces of a manifold mesh or pieces of them, gathered as
    // one component, so it can only fail by reaching the mesh's boundary or its own (a vertex
    // with two boundary arcs), which one boundary loop through every boundary edge once excludes;
    // with V - E + F = 1 it is then a disk.
    static void check_region_disk(const geo::Mesh& m) {
        const auto refuse = [](const std::string& why) {
            throw geo::InputError("the region is not a disk (it may reach the mesh's boundary): " + why);
        };
        const std::size_t nv = m.vertex_count();
        std::vector<std::uint32_t> offset(nv + 1, 0), to(3 * m.face_count());
        for (const auto& t : m.triangles) {
            if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0] || geo::zero_area_face(m, t)) refuse("a face has no area");
            for (int c = 0; c < 3; ++c) ++offset[t[c] + 1];
        }
        for (std::size_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
        std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
        for (const auto& t : m.triangles)
            for (int c = 0; c < 3; ++c) to[fill[t[c]]++] = t[(c + 1) % 3];
        const auto has = [&](std::uint32_t a, std::uint32_t b) {
            std::size_t n = 0;
            for (std::uint32_t i = offset[a]; i < offset[a + 1]; ++i) n += to[i] == b;
            return n;
        };
        std::vector<std::uint32_t> next(nv, kNone);
        std::size_t boundary = 0, directed = 0;
        for (std::uint32_t a = 0; a < nv; ++a)
            for (std::uint32_t i = offset[a]; i < offset[a + 1]; ++i) {
                const std::uint32_t b = to[i];
                ++directed;
                if (has(a, b) != 1)
                    refuse("an edge is in more than two faces, or two faces disagree on their direction");
                if (has(b, a)) continue;
                if (next[a] != kNone) refuse("it touches itself at a vertex");
                next[a] = b, ++boundary;
            }
        const std::size_t edges = boundary + (directed - boundary) / 2;
        if (long(nv) - long(edges) + long(m.face_count()) != 1) refuse("it has a handle or more than one boundary");
        std::size_t loop = 0;
        std::uint32_t v = 0;
        while (v < nv && next[v] == kNone) ++v;
        if (v == nv) refuse("it is closed");
        for (std::uint32_t w = v; loop <= boundary; w = next[w]) {
            ++loop;
            if (next[w] == kNone) refuse("its boundary is open");
            if (next[w] == v) break;
        }
        if (loop != boundary) refuse("it has more than one boundary loop");
        if (boundary < 4) refuse("its boundary has fewer than 4 vertices, one for each corner of the square");
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
    const geo::MeshAdjacency& adj_;
    const std::vector<glm::dvec3>& face_n_;
    const std::vector<std::uint32_t>& across_;  // face_across
    double diagonal_;
    std::vector<std::uint32_t> corners_;
    int n_;
    bool with_outside_;
    std::vector<glm::dvec3> point_pos_;      // inserted points (ids from V on)
    std::vector<std::uint32_t> point_edge_;  // per inserted point, its edge
    std::map<std::pair<std::uint32_t, double>, std::uint32_t> inserted_;
    std::vector<Segment> segments_;
    std::size_t merged_ = 0, fallbacks_ = 0;
};

}  // namespace

QuadRegionCutter::QuadRegionCutter(const geo::Mesh& mesh)
    : mesh_(&mesh), adjacency_(geo::build_adjacency(mesh)), face_normals_(geo::face_normals(mesh)),
      face_across_(face_across(mesh, adjacency_)), diagonal_(mesh.bounds().diagonal()) {}

QuadRegion QuadRegionCutter::cut(const std::array<std::uint32_t, 4>& corners, bool outside) const {
    return cut_polygon({corners.begin(), corners.end()}, outside);
}

QuadRegion QuadRegionCutter::cut_triangle(const std::array<std::uint32_t, 3>& corners, bool outside) const {
    return cut_polygon({corners.begin(), corners.end()}, outside);
}

QuadRegion QuadRegionCutter::cut_polygon(const std::vector<std::uint32_t>& corners, bool outside) const {
    for (std::size_t i = 0; i < corners.size(); ++i) {
        if (corners[i] >= mesh_->vertex_count())
            throw geo::InputError("corner " + std::to_string(corners[i]) + " is not a vertex of the mesh (it has " +
                                  std::to_string(mesh_->vertex_count()) + ")");
        for (std::size_t j = 0; j < i; ++j)
            if (corners[i] == corners[j]) throw geo::InputError("the corners must be distinct vertices");
    }
    return RegionCutter(*mesh_, adjacency_, face_normals_, face_across_, diagonal_, corners, outside).cut();
}

QuadRegion cut_quad_region(const geo::Mesh& mesh, const std::array<std::uint32_t, 4>& corners) {
    return QuadRegionCutter(mesh).cut(corners);
}

QuadRegion cut_triangle_region(const geo::Mesh& mesh, const std::array<std::uint32_t, 3>& corners) {
    return QuadRegionCutter(mesh).cut_triangle(corners);
}

}  // namespace gimg::passes

// Step 3: the polycube map, piece by piece. A slab piece of the mesh and its polycube piece are
// cut to disks along paths that start and end at matching points of their loops, each disk is
// mapped onto the unit circle's disk by a Tutte map (positive weights: one-to-one), with the
// boundary matched by normalised arc length from a common start on every contour; the map is the
// first disk map followed by the inverse of the second. Every piece's system goes into one solve.
#include "piece_disks.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>

namespace gimg::passes::polycube {

namespace {

// A uniform grid over disk triangles, to find the one holding a point.
struct Locator {
    const std::vector<glm::dvec2>* uv = nullptr;
    const std::vector<glm::uvec3>* tri = nullptr;
    int n = 1;
    std::vector<std::vector<std::uint32_t>> cells;
    int cell_of(double c) const { return std::clamp(int((c + 1.0) * 0.5 * n), 0, n - 1); }
    void build(const std::vector<glm::dvec2>& p, const std::vector<glm::uvec3>& t) {
        uv = &p;
        tri = &t;
        n = std::max(1, int(std::sqrt(double(t.size()) / 2.0)));
        cells.assign(std::size_t(n) * n, {});
        for (std::uint32_t f = 0; f < t.size(); ++f) {
            glm::dvec2 lo(1e300), hi(-1e300);
            for (int k = 0; k < 3; ++k) lo = glm::min(lo, p[t[f][k]]), hi = glm::max(hi, p[t[f][k]]);
            for (int y = cell_of(lo.y); y <= cell_of(hi.y); ++y)
                for (int x = cell_of(lo.x); x <= cell_of(hi.x); ++x) cells[std::size_t(y) * n + x].push_back(f);
        }
    }
    static glm::dvec3 bary(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 q) {
        const double d = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if (d == 0.0) return {-1, -1, -1};
        const double l1 = ((q.x - a.x) * (c.y - a.y) - (c.x - a.x) * (q.y - a.y)) / d;
        const double l2 = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / d;
        return {1.0 - l1 - l2, l1, l2};
    }
    // The triangle holding q and its barycentric coordinates; the least outside one when none does.
    std::pair<std::uint32_t, glm::dvec3> locate(glm::dvec2 q) const {
        std::uint32_t best = 0;
        glm::dvec3 best_b(0.0);
        double best_out = 1e300;
        for (int ring = 0; ring <= n; ++ring) {
            const int cx = cell_of(q.x), cy = cell_of(q.y);
            for (int y = std::max(0, cy - ring); y <= std::min(n - 1, cy + ring); ++y)
                for (int x = std::max(0, cx - ring); x <= std::min(n - 1, cx + ring); ++x) {
                    if (std::max(std::abs(x - cx), std::abs(y - cy)) != ring) continue;
                    for (std::uint32_t f : cells[std::size_t(y) * n + x]) {
                        const auto& t = (*tri)[f];
                        const glm::dvec3 b = bary((*uv)[t[0]], (*uv)[t[1]], (*uv)[t[2]], q);
                        const double out = std::max({-b.x, -b.y, -b.z, 0.0});
                        if (out < best_out) best_out = out, best = f, best_b = b;
                    }
                }
            if (best_out <= 1e-12 && ring >= 0) break;
            if (best_out < 1e300 && ring >= 1) break;
        }
        best_b = glm::max(best_b, glm::dvec3(0.0));
        const double sum = best_b.x + best_b.y + best_b.z;
        best_b = sum > 0 ? best_b / sum : glm::dvec3(1.0 / 3.0);
        return {best, best_b};
    }
};

struct PieceWork {
    Local mesh_side, surface_side;
    bool ok = false;
};

}  // namespace

PolycubeMap map_pieces(Context* ctx, const SlicedMesh& sliced, const std::vector<Contour>& contours,
                       const PolycubeSurface& surface, const std::vector<std::vector<std::int32_t>>& loop_contour,
                       const std::vector<PiecePair>& pieces, const std::vector<std::int32_t>& hole_of_face,
                       PolycubeStatistics& stats) {
    PolycubeMap out;
    const geo::Mesh& mesh = sliced.mesh;
    // Per contour: the parameter of its mesh vertices and of its surface loop's vertices.
    std::vector<std::int32_t> contour_of_vertex(mesh.vertex_count(), -1);
    std::vector<std::vector<double>> mesh_u(contours.size());
    std::vector<std::vector<glm::dvec3>> loop_points(contours.size());
    std::vector<std::vector<double>> loop_u(contours.size());
    std::unordered_map<std::uint32_t, std::pair<std::int32_t, double>> surface_vertex_u;
    for (std::size_t c = 0; c < contours.size(); ++c) {
        std::vector<glm::dvec3> p;
        double y_ref = 0.0;
        for (std::uint32_t v : contours[c].vertices) p.push_back(mesh.positions[v]), y_ref += mesh.positions[v].y;
        y_ref /= double(p.size());
        mesh_u[c] = loop_parameter(p, y_ref);
        for (std::size_t i = 0; i < p.size(); ++i) contour_of_vertex[contours[c].vertices[i]] = std::int32_t(c);
        for (std::size_t plane = 0; plane < surface.loops.size(); ++plane)
            for (std::size_t l = 0; l < surface.loops[plane].size(); ++l)
                if (loop_contour[plane][l] == std::int32_t(c)) {
                    for (std::uint32_t v : surface.loops[plane][l]) loop_points[c].push_back(surface.mesh.positions[v]);
                    loop_u[c] = loop_parameter(loop_points[c], y_ref);
                    for (std::size_t i = 0; i < surface.loops[plane][l].size(); ++i)
                        surface_vertex_u[surface.loops[plane][l][i]] = {std::int32_t(c), loop_u[c][i]};
                }
    }
    const auto mesh_vertex_u = [&](std::uint32_t v) {
        const std::int32_t c = contour_of_vertex[v];
        const auto& vs = contours[c].vertices;
        return mesh_u[c][std::size_t(std::find(vs.begin(), vs.end(), v) - vs.begin())];
    };

    std::vector<PieceWork> work(pieces.size());
    std::size_t failed_loops = 0, failed_contours = 0, failed_paths = 0, failed_boundaries = 0;
    for (std::size_t pi = 0; pi < pieces.size(); ++pi) {
        PieceWork& w = work[pi];
        // The two sides as local meshes.
        const auto make_local = [&](Local& m, const std::vector<std::uint32_t>& tris, const geo::Mesh& src,
                                    bool mesh_side) {
            std::unordered_map<std::uint32_t, std::uint32_t> id;
            for (std::uint32_t f : tris) {
                glm::uvec3 t;
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t g = src.triangles[f][k];
                    const auto [it, added] = id.emplace(g, std::uint32_t(m.pos.size()));
                    if (added) {
                        m.pos.push_back(src.positions[g]);
                        m.global.push_back(mesh_side ? g : kNone);
                        m.origin.push_back(it->second);
                        std::int32_t c = -1;
                        double u = 0.0;
                        if (mesh_side && contour_of_vertex[g] >= 0) c = contour_of_vertex[g], u = mesh_vertex_u(g);
                        if (!mesh_side) {
                            const auto s = surface_vertex_u.find(g);
                            if (s != surface_vertex_u.end()) c = s->second.first, u = s->second.second;
                        }
                        m.contour.push_back(c);
                        m.u.push_back(u);
                    }
                    t[k] = it->second;
                }
                m.tri.push_back(t);
                m.tri_source.push_back(f);
            }
        };
        make_local(w.mesh_side, pieces[pi].mesh_triangles, mesh, true);
        make_local(w.surface_side, pieces[pi].surface_triangles, surface.mesh, false);
        Local& S = w.mesh_side;
        Local& T = w.surface_side;
        std::vector<std::vector<std::uint32_t>> s_loops, t_loops;
        try {
            s_loops = boundary_loops(S.tri);
            t_loops = boundary_loops(T.tri);
        } catch (const geo::InputError&) {  // two loops through one vertex
            s_loops.clear();
        }
        if (s_loops.empty() || s_loops.size() != t_loops.size()) {
            ++out.cut_mismatch, ++failed_loops;
            continue;
        }
        std::map<std::int32_t, std::size_t> t_loop_of;
        for (std::size_t l = 0; l < t_loops.size(); ++l) t_loop_of[T.contour[t_loops[l][0]]] = l;
        bool ok = true;
        for (const auto& l : s_loops) ok = ok && S.contour[l[0]] >= 0 && t_loop_of.count(S.contour[l[0]]);
        if (!ok) {
            ++out.cut_mismatch, ++failed_contours;
            continue;
        }
        // Cuts joining the loops into one tree, each from a loop not yet joined to the nearest
        // joined one, on the mesh side first; the surface side cuts between the points of the same
        // parameters. Where the cuts wall a loop off, the tree is grown from another loop.
        std::int32_t c0 = -1;
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> s_cut_of, t_cut_of;
        std::uint32_t s_start = 0, t_start = 0;
        const Local s_before = S;
        Local t_before = T;
        // Where the surface side's paths wall each other off from every root, that side is split
        // finer (the same surface) and the roots are tried again, at most twice.
        for (int finer = 0; finer <= 2; ++finer) {
            bool t_blocked = false;
            if (finer > 0) {
                subdivide(t_before);
                t_loops = boundary_loops(t_before.tri);
            }
            for (std::size_t root = 0; root < s_loops.size(); ++root) {
                S = s_before, T = t_before;
                s_cut_of.clear(), t_cut_of.clear();
                ok = true;
                std::rotate(s_loops.begin(), s_loops.begin() + std::ptrdiff_t(root > 0 ? 1 : 0), s_loops.end());
                c0 = S.contour[s_loops[0][0]];
                auto nb = neighbours(S);
                std::vector<std::uint8_t> free(S.pos.size(), 1), target(S.pos.size(), 0);
                for (const auto& l : s_loops)
                    for (std::uint32_t v : l) free[v] = 0;
                for (std::uint32_t v : s_loops[0]) target[v] = 1;
                std::vector<std::uint8_t> joined(s_loops.size(), 0);
                joined[0] = 1;
                const auto loop_of = [&](std::uint32_t v) {
                    for (std::size_t l = 0; l < s_loops.size(); ++l)
                        if (S.contour[s_loops[l][0]] == S.contour[v]) return l;
                    return std::size_t(0);
                };
                struct Cut {
                    std::int32_t child, parent;
                    double child_u, parent_u;
                };
                std::vector<Cut> cuts;
                for (std::size_t step = 1; step < s_loops.size() && ok; ++step) {
                    std::vector<std::uint32_t> sources;
                    for (std::size_t l = 0; l < s_loops.size(); ++l)
                        if (!joined[l])
                            for (std::uint32_t v : s_loops[l])
                                if (target[v] == 0) sources.push_back(v);
                    const auto path = shortest_path(S, nb, sources, target, free);
                    if (path.empty()) {
                        ok = false;
                        break;
                    }
                    const int id = int(cuts.size());
                    for (std::size_t i = 0; i + 1 < path.size(); ++i) s_cut_of[std::minmax(path[i], path[i + 1])] = id;
                    for (std::uint32_t v : path) free[v] = 0;
                    target[path.back()] = 0;
                    const std::size_t child = loop_of(path.front());
                    joined[child] = 1;
                    for (std::uint32_t v : s_loops[child])
                        if (v != path.front()) target[v] = 1;
                    if (step == 1) s_start = path.back();
                    cuts.push_back(
                        {S.contour[path.front()], S.contour[path.back()], S.u[path.front()], S.u[path.back()]});
                }
                if (ok && !cuts.empty()) {
                    // The same points on the surface side, then paths between them.
                    std::vector<std::pair<std::uint32_t, std::uint32_t>> ends;
                    // T's loops, which vertex_at keeps up to date as it splits their edges.
                    std::vector<std::vector<std::uint32_t>> t_loops_now = t_loops;
                    const auto at = [&](std::int32_t c, double u) {
                        for (auto& l : t_loops_now)
                            if (T.contour[l[0]] == c) return vertex_at(T, l, u, loop_points[c], loop_u[c]);
                        throw geo::InputError("internal: polycube loop lost");
                    };
                    for (const Cut& c : cuts) {
                        const std::uint32_t tb = at(c.child, c.child_u);
                        const std::uint32_t ta = at(c.parent, c.parent_u);
                        ends.push_back({tb, ta});
                    }
                    auto tnb = neighbours(T);
                    std::vector<std::uint8_t> tfree(T.pos.size(), 1);
                    for (const auto& l : t_loops_now)
                        for (std::uint32_t v : l) tfree[v] = 0;
                    for (std::size_t j = 0; j < ends.size() && ok; ++j) {
                        std::vector<std::uint8_t> target_t(T.pos.size(), 0);
                        target_t[ends[j].second] = 1;
                        const auto path = shortest_path(T, tnb, {ends[j].first}, target_t, tfree);
                        if (path.empty()) {
                            t_blocked = true;
                            ok = false;
                            break;
                        }
                        for (std::size_t i = 0; i + 1 < path.size(); ++i)
                            t_cut_of[std::minmax(path[i], path[i + 1])] = int(j);
                        for (std::uint32_t v : path) tfree[v] = 0;
                        if (j == 0) t_start = path.back();
                    }
                }
                if (ok) break;
            }
            if (ok || !t_blocked) break;
        }
        if (!ok) {
            ++out.cut_mismatch, ++failed_paths;
            continue;
        }
        std::set<std::pair<std::uint32_t, std::uint32_t>> s_cut, t_cut;
        for (const auto& [e, j] : s_cut_of) s_cut.insert(e);
        for (const auto& [e, j] : t_cut_of) t_cut.insert(e);
        cut_open(S, s_cut);
        cut_open(T, t_cut);
        bool s_ok = false, t_ok = false;
        const auto s_segs = disk_segments(S, s_cut_of, s_start, c0 + 1, s_ok);
        const auto t_segs = disk_segments(T, t_cut_of, t_start, c0 + 1, t_ok);
        ok = s_ok && t_ok && s_segs.size() == t_segs.size();
        for (std::size_t s = 0; ok && s < s_segs.size(); ++s) ok = s_segs[s].kind == t_segs[s].kind;
        if (!ok) {
            ++out.cut_mismatch, ++failed_boundaries;
            continue;
        }
        double s_total = 0.0, t_total = 0.0;
        for (std::size_t s = 0; s < s_segs.size(); ++s) s_total += s_segs[s].length, t_total += t_segs[s].length;
        std::vector<double> span(s_segs.size());
        for (std::size_t s = 0; s < s_segs.size(); ++s)
            span[s] = kTwoPi * 0.5 * (s_segs[s].length / s_total + t_segs[s].length / t_total);
        S.disk.assign(S.pos.size(), glm::dvec2(0.0));
        T.disk.assign(T.pos.size(), glm::dvec2(0.0));
        place_boundary(S, s_segs, span);
        place_boundary(T, t_segs, span);
        w.ok = true;
    }

    if (out.cut_mismatch)
        out.note = std::to_string(out.cut_mismatch) + " of " + std::to_string(pieces.size()) +
                   " pieces could not be cut to matching disks (loops differ: " + std::to_string(failed_loops) +
                   ", loops unmatched: " + std::to_string(failed_contours) +
                   ", no disjoint cut: " + std::to_string(failed_paths) +
                   ", boundaries differ: " + std::to_string(failed_boundaries) + ")";
    // One Tutte solve for every piece's mesh side, one for every surface side.
    for (int side = 0; side < 2; ++side) {
        geo::Mesh all;
        std::vector<std::uint8_t> fixed;
        std::vector<double> values;
        std::vector<std::uint32_t> first(pieces.size(), 0);
        for (std::size_t pi = 0; pi < pieces.size(); ++pi) {
            if (!work[pi].ok) continue;
            Local& m = side ? work[pi].surface_side : work[pi].mesh_side;
            first[pi] = std::uint32_t(all.positions.size());
            std::vector<std::uint8_t> on_boundary(m.pos.size(), 0);
            for (const auto& l : boundary_loops(m.tri))
                for (std::uint32_t v : l) on_boundary[v] = 1;
            for (std::size_t v = 0; v < m.pos.size(); ++v) {
                all.positions.push_back(m.pos[v]);
                fixed.push_back(on_boundary[v]);
                values.push_back(m.disk[v].x);
                values.push_back(m.disk[v].y);
            }
            for (const auto& t : m.tri) all.triangles.push_back(t + glm::uvec3(first[pi]));
        }
        if (all.triangles.empty()) break;
        const geo::MeshAdjacency adj = geo::build_adjacency(all);
        const SolveResult r = solve(ctx, positive_laplacian(all, adj, fixed, values, 2), stats);
        if (!r.converged)
            out.note += (out.note.empty() ? "" : "; ") + std::string("a Tutte solve stopped at residual ") +
                        std::to_string(r.residual);
        for (std::size_t pi = 0; pi < pieces.size(); ++pi) {
            if (!work[pi].ok) continue;
            Local& m = side ? work[pi].surface_side : work[pi].mesh_side;
            for (std::size_t v = 0; v < m.pos.size(); ++v)
                m.disk[v] = {r.x[2 * (first[pi] + v)], r.x[2 * (first[pi] + v) + 1]};
        }
    }

    // Compose: every mesh-side point found in the surface side's disk.
    out.image.assign(mesh.vertex_count(), glm::dvec3(std::nan("")));
    out.image_axis.assign(mesh.vertex_count(), 0);
    out.surface_hole.assign(surface.mesh.face_count(), 0);
    std::int32_t holes = 0;
    for (std::int32_t h : hole_of_face) holes = std::max(holes, h + 1);
    std::vector<std::uint8_t> marked(std::size_t(holes), 0);
    for (std::size_t pi = 0; pi < pieces.size(); ++pi) {
        if (!work[pi].ok) continue;
        const Local& S = work[pi].mesh_side;
        const Local& T = work[pi].surface_side;
        Locator on_surface, on_mesh;
        on_surface.build(T.disk, T.tri);
        on_mesh.build(S.disk, S.tri);
        // Both disk maps must be embeddings: every triangle turning the way the whole disk does.
        for (const Local* m : {&S, &T}) {
            double total = 0.0;
            std::vector<double> area(m->tri.size());
            for (std::size_t f = 0; f < m->tri.size(); ++f) {
                const glm::dvec2 a = m->disk[m->tri[f][0]], b = m->disk[m->tri[f][1]], c = m->disk[m->tri[f][2]];
                area[f] = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
                total += area[f];
            }
            for (double x : area)
                if (!(x * total > 0.0)) ++out.disk_flips;
        }
        for (std::size_t v = 0; v < S.pos.size(); ++v) {
            const auto [f, b] = on_surface.locate(S.disk[v]);
            const auto& t = T.tri[f];
            glm::dvec3 p = b.x * T.pos[t[0]] + b.y * T.pos[t[1]] + b.z * T.pos[t[2]];
            if (S.contour[v] >= 0) {  // on a cut: the point both pieces agree on, by parameter
                const glm::dvec3 q = point_at(loop_points[S.contour[v]], loop_u[S.contour[v]], S.u[v]);
                out.boundary_snap = std::max(out.boundary_snap, glm::length(q - p));
                p = q;
            }
            out.image[S.global[v]] = p;
            out.image_axis[S.global[v]] = surface.axis[T.tri_source[f]];
        }
        for (std::size_t f = 0; f < T.tri.size(); ++f) {
            const auto& t = T.tri[f];
            const auto [g, b] = on_mesh.locate((T.disk[t[0]] + T.disk[t[1]] + T.disk[t[2]]) / 3.0);
            const std::int32_t h = hole_of_face[sliced.source_face[S.tri_source[g]]];
            if (h >= 0) out.surface_hole[T.tri_source[f]] = 1, marked[std::size_t(h)] = 1;
        }
        // A cap too small to hold a polycube triangle's centre still marks the one under its own.
        for (std::size_t f = 0; f < S.tri.size(); ++f) {
            const std::int32_t h = hole_of_face[sliced.source_face[S.tri_source[f]]];
            if (h < 0 || marked[std::size_t(h)]) continue;
            const auto& t = S.tri[f];
            const auto [g, b] = on_surface.locate((S.disk[t[0]] + S.disk[t[1]] + S.disk[t[2]]) / 3.0);
            out.surface_hole[T.tri_source[g]] = 1;
            marked[std::size_t(h)] = 1;
        }
        ++out.pieces_mapped;
    }
    out.holes_marked = std::size_t(std::count(marked.begin(), marked.end(), 1));
    return out;
}

}  // namespace gimg::passes::polycube

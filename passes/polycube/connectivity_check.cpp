// The connectivity check (spec sec. 3.2, step 2-3): which contour each loop of the polycube's walls
// stands for, and whether every slab of the polycube joins the same contours as the mesh's slab,
// piece by piece, each piece of genus 0.
#include "polycube_parts.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <tuple>

namespace gimg::passes::polycube {

namespace {

using Pieces = SlabPieces;

// Components of triangles of the same slab joined across edges; their contour sets.
Pieces slab_pieces(const std::vector<glm::uvec3>& tris, const std::vector<std::uint32_t>& slab,
                   const std::function<std::int32_t(std::uint32_t)>& contour_of) {
    const std::vector<std::uint32_t> root =
        join_across_edges(tris, [&](std::uint32_t f, std::uint32_t g) { return slab[f] == slab[g]; });
    Pieces p;
    constexpr std::size_t kNoPiece = std::size_t(-1);
    std::vector<std::size_t> index(tris.size(), kNoPiece);  // per root face, its piece
    for (std::uint32_t f = 0; f < tris.size(); ++f) {
        std::size_t& piece = index[root[f]];
        if (piece == kNoPiece) {
            piece = p.triangles.size();
            p.triangles.emplace_back();
            p.slab.push_back(slab[f]);
            p.contours.emplace_back();
        }
        p.triangles[piece].push_back(f);
        for (int k = 0; k < 3; ++k)
            if (const std::int32_t c = contour_of(tris[f][k]); c >= 0) p.contours[piece].insert(c);
    }
    for (const auto& t : p.triangles) {
        std::vector<std::uint32_t> vs;
        std::vector<std::uint64_t> es;
        std::vector<glm::uvec3> local;
        for (std::uint32_t f : t) {
            local.push_back(tris[f]);
            for (int k = 0; k < 3; ++k)
                vs.push_back(tris[f][k]), es.push_back(edge_key(tris[f][k], tris[f][(k + 1) % 3]));
        }
        std::sort(vs.begin(), vs.end());
        vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
        std::sort(es.begin(), es.end());
        es.erase(std::unique(es.begin(), es.end()), es.end());
        const long long chi = (long long)vs.size() - (long long)es.size() + (long long)t.size();
        try {
            p.disk_like.push_back(chi == 2 - (long long)boundary_loops(local).size());
        } catch (const geo::InputError&) {  // two loops through one vertex: not a genus-0 surface with holes
            p.disk_like.push_back(false);
        }
    }
    return p;
}

}  // namespace

SlabPieces mesh_slab_pieces(const SlicedMesh& sliced, const std::vector<Contour>& contours,
                            const std::vector<double>& plane_z) {
    std::vector<std::int32_t> contour_of(sliced.mesh.vertex_count(), -1);
    for (std::size_t c = 0; c < contours.size(); ++c)
        for (std::uint32_t v : contours[c].vertices) contour_of[v] = std::int32_t(c);
    std::vector<std::uint32_t> mesh_slab(sliced.mesh.face_count());
    for (std::size_t f = 0; f < mesh_slab.size(); ++f) {
        const auto& t = sliced.mesh.triangles[f];
        const double zc =
            (sliced.mesh.positions[t[0]].z + sliced.mesh.positions[t[1]].z + sliced.mesh.positions[t[2]].z) / 3.0;
        mesh_slab[f] = std::uint32_t(std::upper_bound(plane_z.begin(), plane_z.end(), zc) - plane_z.begin());
    }
    return slab_pieces(sliced.mesh.triangles, mesh_slab, [&](std::uint32_t v) { return contour_of[v]; });
}

JoinedContours joined_contours(const SlabPieces& ms, const std::vector<Contour>& contours,
                               const std::vector<double>& plane_z) {
    JoinedContours joined(plane_z.size() + 1);
    for (std::size_t i = 0; i < ms.triangles.size(); ++i) {
        const std::uint32_t slab = ms.slab[i];
        if (slab == 0 || slab >= plane_z.size()) continue;
        for (const std::int32_t lower : ms.contours[i])
            for (const std::int32_t upper : ms.contours[i])
                if (contours[lower].plane + 1 == slab && contours[upper].plane == slab)
                    joined[slab].insert({lower, upper});
    }
    return joined;
}

std::vector<std::vector<std::int32_t>> match_loops(const PolycubeSurface& surface, const std::vector<Contour>& contours,
                                                   std::size_t plane_count) {
    std::vector<std::vector<std::size_t>> contour_ids(plane_count);
    for (std::size_t c = 0; c < contours.size(); ++c) contour_ids[contours[c].plane].push_back(c);
    std::vector<std::vector<std::int32_t>> loop_contour(plane_count);
    for (std::size_t p = 0; p < plane_count; ++p) {
        const auto& ls = surface.loops[p];
        loop_contour[p].assign(ls.size(), -1);
        std::vector<std::tuple<double, std::size_t, std::size_t>> cost;
        for (std::size_t l = 0; l < ls.size(); ++l) {
            std::vector<glm::dvec2> poly;
            for (std::uint32_t v : ls[l]) poly.push_back({surface.mesh.positions[v].x, surface.mesh.positions[v].y});
            for (std::size_t ci = 0; ci < contour_ids[p].size(); ++ci) {
                const auto& cl = contours[contour_ids[p][ci]].closed;
                const std::size_t step = std::max<std::size_t>(1, cl.size() / 48);
                double d = 0.0;
                std::size_t count = 0;
                for (std::size_t i = 0; i < cl.size(); i += step, ++count) d += distance_to_loop(cl[i], poly);
                cost.emplace_back(d / double(count), l, ci);
            }
        }
        std::sort(cost.begin(), cost.end());
        std::vector<bool> used(contour_ids[p].size(), false);
        for (const auto& [d, l, ci] : cost)
            if (loop_contour[p][l] < 0 && !used[ci])
                loop_contour[p][l] = std::int32_t(contour_ids[p][ci]), used[ci] = true;
    }
    return loop_contour;
}

SlabCheck check_slabs(const SlabPieces& ms, const std::vector<Contour>& contours, const PolycubeSurface& surface,
                      const std::vector<std::vector<std::int32_t>>& loop_contour, const std::vector<double>& plane_z) {
    SlabCheck check;
    std::vector<std::size_t> contours_on(plane_z.size(), 0);
    for (const auto& c : contours) ++contours_on[c.plane];
    // The connectivity check: every slab piece of the mesh (genus 0) against the polycube's.
    std::map<std::uint32_t, std::int32_t> surface_contour;
    for (std::size_t p = 0; p < plane_z.size(); ++p)
        for (std::size_t l = 0; l < surface.loops[p].size(); ++l)
            for (std::uint32_t v : surface.loops[p][l]) surface_contour[v] = loop_contour[p][l];
    const Pieces ps = slab_pieces(surface.mesh.triangles, surface.slab, [&](std::uint32_t v) {
        const auto it = surface_contour.find(v);
        return it == surface_contour.end() ? -1 : it->second;
    });
    std::map<std::pair<std::uint32_t, std::set<std::int32_t>>, std::size_t> surface_piece;
    for (std::size_t i = 0; i < ps.triangles.size(); ++i)
        if (ps.disk_like[i]) surface_piece[{ps.slab[i], ps.contours[i]}] = i;  // a handle in a piece matches nothing
    std::vector<std::size_t> mesh_pieces_in(plane_z.size() + 1, 0), surface_pieces_in(plane_z.size() + 1, 0);
    for (std::size_t i = 0; i < ps.triangles.size(); ++i) ++surface_pieces_in[ps.slab[i]];
    for (std::size_t i = 0; i < ms.triangles.size(); ++i) {
        ++mesh_pieces_in[ms.slab[i]];
        const auto it = surface_piece.find({ms.slab[i], ms.contours[i]});
        if (it == surface_piece.end() || !ms.disk_like[i]) {
            if (check.bad_slabs.insert(ms.slab[i]).second)
                check.reasons.push_back(
                    "slab " + std::to_string(ms.slab[i]) + ": a mesh piece " +
                    (ms.disk_like[i] ? "joins contours no polycube piece joins" : "is not genus 0"));
            continue;
        }
        check.pairs.push_back({ms.triangles[i], ps.triangles[it->second]});
    }
    for (std::size_t slab = 0; slab <= plane_z.size(); ++slab)
        if (mesh_pieces_in[slab] != surface_pieces_in[slab] && check.bad_slabs.insert(std::uint32_t(slab)).second)
            check.reasons.push_back("slab " + std::to_string(slab) + ": " + std::to_string(mesh_pieces_in[slab]) +
                                    " mesh pieces, " + std::to_string(surface_pieces_in[slab]) + " polycube pieces");
    for (std::size_t p = 0; p < plane_z.size(); ++p)  // a plane whose loops and contours differ in number
        if (surface.loops[p].size() != contours_on[p]) {
            check.bad_planes.push_back(p);
            check.reasons.push_back("plane " + std::to_string(p) + ": " + std::to_string(contours_on[p]) +
                                    " contours, " + std::to_string(surface.loops[p].size()) + " polycube loops");
        }
    check.mesh_pieces = ms.triangles.size();
    return check;
}

}  // namespace gimg::passes::polycube

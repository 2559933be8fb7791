// Where a repair plane goes inside a slab that does not match. A noisy surface (a pitted scan) has
// many more critical heights in z than its harmonic function has saddles: a plane through the
// pits adds a contour per pit, each a chance for the layers to differ from the mesh. So the plane
// goes where the section has the fewest loops, and where a slab piece of the mesh has a handle,
// at a height that cuts the handle (every piece above and below of genus 0).
#include "polycube_parts.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace gimg::passes::polycube {

std::size_t section_loops(const geo::Mesh& mesh, double h) {
    // Every edge crossing the plane is a point of the section; a triangle crossing it joins two.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> point;
    std::vector<std::uint32_t> parent;
    const auto find = [&](std::uint32_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    };
    for (const auto& t : mesh.triangles) {
        std::uint32_t ends[2], count = 0;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if ((mesh.positions[a].z > h) == (mesh.positions[b].z > h)) continue;
            const auto [it, added] = point.emplace(std::minmax(a, b), std::uint32_t(parent.size()));
            if (added) parent.push_back(it->second);
            if (count < 2) ends[count++] = it->second;
        }
        if (count == 2) parent[find(ends[0])] = find(ends[1]);
    }
    std::size_t loops = 0;
    for (std::uint32_t i = 0; i < parent.size(); ++i) loops += find(i) == i;
    return loops;
}

namespace {

// Whether cutting `piece` (a triangle set of `sliced`) at height h leaves only pieces of genus 0.
bool cuts_every_handle(const SlicedMesh& sliced, const std::vector<std::uint32_t>& piece, double h) {
    geo::Mesh sub;
    std::map<std::uint32_t, std::uint32_t> index;
    for (std::uint32_t f : piece) {
        glm::uvec3 t;
        for (int k = 0; k < 3; ++k) {
            const auto [it, added] = index.emplace(sliced.mesh.triangles[f][k], std::uint32_t(sub.positions.size()));
            if (added) sub.positions.push_back(sliced.mesh.positions[it->first]);
            t[k] = it->second;
        }
        sub.triangles.push_back(t);
    }
    const SlicedMesh cut = slice_mesh(sub, {h});
    const std::vector<Contour> contours = plane_contours(cut, 1, cut.mesh.face_count());
    const SlabPieces pieces = mesh_slab_pieces(cut, contours, {h});
    return std::all_of(pieces.disk_like.begin(), pieces.disk_like.end(), [](bool d) { return d; });
}

}  // namespace

std::vector<double> quiet_heights(const geo::Mesh& mesh, double lo, double hi, double prefer) {
    // Halfway between neighbouring vertex heights: as far from the vertices as the mesh allows.
    std::vector<double> zs;
    for (const auto& p : mesh.positions)
        if (p.z > lo && p.z < hi) zs.push_back(p.z);
    std::sort(zs.begin(), zs.end());
    zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
    std::vector<double> candidates;
    if (prefer > lo && prefer < hi) candidates.push_back(prefer);
    const std::size_t step = std::max<std::size_t>(1, zs.size() / 96);
    for (std::size_t i = 0; i + 1 < zs.size(); i += step) candidates.push_back(0.5 * (zs[i] + zs[i + 1]));
    std::vector<std::tuple<std::size_t, double, double>> scored;  // (loops, distance to prefer, height)
    for (double h : candidates) scored.emplace_back(section_loops(mesh, h), std::abs(h - prefer), h);
    std::sort(scored.begin(), scored.end());
    std::vector<double> out;
    for (const auto& s : scored) out.push_back(std::get<2>(s));
    return out;
}

double repair_height(const geo::Mesh& mesh, const SlicedMesh& sliced, const std::vector<std::uint32_t>* handle,
                     double lo, double hi) {
    // The middle half of the slab, or all of it when a handle must be cut.
    const double margin = handle ? 1e-3 * (hi - lo) : 0.25 * (hi - lo);
    const std::vector<double> heights = quiet_heights(mesh, lo + margin, hi - margin, 0.5 * (lo + hi));
    if (handle)
        for (double h : heights)
            if (cuts_every_handle(sliced, *handle, h)) return h;
    return heights.empty() ? 0.5 * (lo + hi) : heights.front();
}

}  // namespace gimg::passes::polycube

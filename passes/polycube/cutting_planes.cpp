// Step 2-1: the horizontal cutting planes, and the mesh cut along them into slab pieces.
#include "polycube_parts.h"

#include "gimg/geometry/error.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace gimg::passes {

namespace {

// floor(gap / dz) planes evenly spaced strictly inside (lo, hi), so every sub-gap is below dz.
void insert_planes(double lo, double hi, double dz, std::vector<CuttingPlane>& out) {
    if (!(dz > 0.0) || hi - lo <= dz) return;
    const std::size_t n = std::size_t(std::floor((hi - lo) / dz));
    for (std::size_t j = 1; j <= n; ++j) out.push_back({lo + (hi - lo) * double(j) / double(n + 1), true});
}

}  // namespace

std::vector<CuttingPlane> cutting_planes(std::vector<double> z, double dz, double merge) {
    if (z.size() < 2) throw geo::InputError("cutting planes need at least a minimum and a maximum height");
    std::sort(z.begin(), z.end());
    std::vector<double> merged{z.front()};
    for (std::size_t i = 1; i < z.size(); ++i)
        if (z[i] - merged.back() >= merge) merged.push_back(z[i]);
    if (merged.size() < 2) merged.push_back(z.back());
    if (merged.back() != z.back()) merged.back() = z.back();  // the maximum stays the top bound

    std::vector<CuttingPlane> mid;
    for (std::size_t i = 0; i + 1 < merged.size(); ++i) mid.push_back({0.5 * (merged[i] + merged[i + 1]), false});
    std::vector<CuttingPlane> out;
    insert_planes(merged.front(), mid.front().z, dz, out);  // the end gap below (spec sec. 3.2 item 6)
    for (std::size_t i = 0; i < mid.size(); ++i) {
        out.push_back(mid[i]);
        insert_planes(mid[i].z, i + 1 < mid.size() ? mid[i + 1].z : merged.back(), dz, out);
    }
    std::sort(out.begin(), out.end(), [](const CuttingPlane& a, const CuttingPlane& b) { return a.z < b.z; });
    return out;
}

namespace polycube {

SlicedMesh slice_mesh(const geo::Mesh& mesh, const std::vector<double>& plane_z, std::vector<glm::dvec3>* carried) {
    SlicedMesh s;
    s.mesh.positions = mesh.positions;
    s.mesh.triangles = mesh.triangles;
    s.plane_of.assign(mesh.vertex_count(), -1);
    s.source_face.resize(mesh.face_count());
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) s.source_face[f] = f;
    for (std::size_t p = 0; p < plane_z.size(); ++p) {
        const double z = plane_z[p];
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> split;
        const auto cut = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto it = split.find(key);
            if (it != split.end()) return it->second;
            const glm::dvec3 pa = s.mesh.positions[a], pb = s.mesh.positions[b];
            const double t = (z - pa.z) / (pb.z - pa.z);
            glm::dvec3 q = pa + t * (pb - pa);
            q.z = z;
            const std::uint32_t id = std::uint32_t(s.mesh.positions.size());
            s.mesh.positions.push_back(q);
            if (carried) carried->push_back((*carried)[a] + t * ((*carried)[b] - (*carried)[a]));
            s.plane_of.push_back(std::int32_t(p));
            split.emplace(key, id);
            return id;
        };
        const std::size_t count = s.mesh.triangles.size();
        for (std::size_t f = 0; f < count; ++f) {
            const glm::uvec3 t = s.mesh.triangles[f];
            bool above[3];
            for (int k = 0; k < 3; ++k) above[k] = s.mesh.positions[t[k]].z > z;
            if (above[0] == above[1] && above[1] == above[2]) continue;
            // The corner alone on its side, then the other two in the triangle's order.
            const int lone = above[0] == above[1] ? 2 : above[0] == above[2] ? 1 : 0;
            const std::uint32_t a = t[lone], b = t[(lone + 1) % 3], c = t[(lone + 2) % 3];
            const std::uint32_t p_ab = cut(a, b), q_ca = cut(a, c);
            s.mesh.triangles[f] = {a, p_ab, q_ca};
            s.mesh.triangles.push_back({p_ab, b, c});
            s.mesh.triangles.push_back({p_ab, c, q_ca});
            s.source_face.push_back(s.source_face[f]);
            s.source_face.push_back(s.source_face[f]);
        }
    }
    return s;
}

std::vector<Contour> plane_contours(const SlicedMesh& s, std::size_t plane_count, std::size_t original_faces) {
    // In-plane edges: both ends on the same plane. Each lies in two triangles of one source face.
    struct Neighbour {
        std::uint32_t v[2]{geo::kInvalidIndex, geo::kInvalidIndex};
        std::uint8_t gap[2]{0, 0};
    };
    std::map<std::uint32_t, Neighbour> ring;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint8_t> edges;
    for (std::size_t f = 0; f < s.mesh.triangles.size(); ++f) {
        const glm::uvec3 t = s.mesh.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if (s.plane_of[a] < 0 || s.plane_of[a] != s.plane_of[b]) continue;
            edges[std::minmax(a, b)] = s.source_face[f] >= original_faces ? 1 : 0;
        }
    }
    for (const auto& [e, gap] : edges)
        for (int side = 0; side < 2; ++side) {
            const std::uint32_t v = side ? e.second : e.first, w = side ? e.first : e.second;
            Neighbour& n = ring[v];
            const int slot = n.v[0] == geo::kInvalidIndex ? 0 : 1;
            if (n.v[slot] != geo::kInvalidIndex)
                throw geo::InputError("a plane section branches at a vertex (the mesh touches itself there)");
            n.v[slot] = w;
            n.gap[slot] = gap;
        }
    std::vector<Contour> contours;
    std::map<std::uint32_t, bool> seen;
    for (std::size_t p = 0; p < plane_count; ++p)
        for (const auto& [start, n0] : ring) {
            if (s.plane_of[start] != std::int32_t(p) || seen[start]) continue;
            Contour c;
            c.plane = std::uint32_t(p);
            std::uint32_t prev = geo::kInvalidIndex, v = start;
            while (true) {
                seen[v] = true;
                c.vertices.push_back(v);
                const Neighbour& n = ring[v];
                if (n.v[1] == geo::kInvalidIndex) throw geo::InputError("a plane section ends inside the mesh");
                const int slot = n.v[0] != prev ? 0 : 1;
                c.gap.push_back(n.gap[slot]);
                prev = v;
                v = n.v[slot];
                if (v == start) break;
            }
            contours.push_back(std::move(c));
        }
    return contours;
}

}  // namespace polycube
}  // namespace gimg::passes

// The base domain subdivided 4-to-1 (sec. 2.4): nested vertex ids, one midpoint per edge, and
// every vertex's exact place in a base triangle.
#include "gimg/geometry/error.h"
#include "gimg/passes/maps.h"

#include <string>
#include <unordered_map>

namespace gimg::passes {

namespace {

// A face of the current level: its base triangle and its corners' barycentric coordinates there,
// so that midpoints get exact dyadic coordinates in one base triangle.
struct FacePlace {
    std::uint32_t base;
    glm::dvec3 corner[3];
};

}  // namespace

SemiRegularMesh subdivide_base(const geo::Mesh& base, std::uint32_t levels) {
    if (levels > 8) throw geo::InputError("semi-regular remesh: " + std::to_string(levels) + " levels (at most 8)");
    const auto v0 = std::uint32_t(base.vertex_count());
    for (const glm::uvec3& t : base.triangles)
        for (int k = 0; k < 3; ++k)
            if (t[k] >= v0)
                throw geo::InputError("semi-regular remesh: base vertex " + std::to_string(t[k]) + " out of range (" +
                                      std::to_string(v0) + " vertices)");
    if (base.face_count() << (2 * levels) > std::size_t(1) << 31)
        throw geo::InputError("semi-regular remesh: too many faces at level " + std::to_string(levels));

    SemiRegularMesh out;
    out.faces.push_back(base.triangles);
    out.vertex_count.push_back(v0);
    out.base_point.assign(v0, SurfacePoint{});
    std::vector<bool> placed(v0, false);
    std::vector<FacePlace> place(base.face_count());
    for (std::uint32_t f = 0; f < base.face_count(); ++f) {
        place[f] = {f, {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)}};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = base.triangles[f][k];
            if (!placed[v]) out.base_point[v] = {f, place[f].corner[k]};
            placed[v] = true;
        }
    }

    for (std::uint32_t j = 0; j < levels; ++j) {
        const std::vector<glm::uvec3>& coarse = out.faces[j];
        std::uint32_t next = out.vertex_count[j];
        std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
        midpoint.reserve(coarse.size() * 2);
        std::vector<glm::uvec3> fine;
        fine.reserve(coarse.size() * 4);
        std::vector<FacePlace> fine_place;
        fine_place.reserve(coarse.size() * 4);
        for (std::size_t f = 0; f < coarse.size(); ++f) {
            const glm::uvec3 t = coarse[f];
            const FacePlace& p = place[f];
            std::uint32_t mid[3];  // on edges (0,1), (1,2), (2,0)
            glm::dvec3 mid_bary[3];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = t[k], b = t[(k + 1) % 3];
                mid_bary[k] = (p.corner[k] + p.corner[(k + 1) % 3]) * 0.5;
                const std::uint64_t key = a < b ? (std::uint64_t(a) << 32 | b) : (std::uint64_t(b) << 32 | a);
                auto [it, added] = midpoint.try_emplace(key, next);
                if (added) {
                    out.parents.push_back({a, b});
                    out.base_point.push_back({p.base, mid_bary[k]});
                    ++next;
                }
                mid[k] = it->second;
            }
            const std::uint32_t a = t[0], b = t[1], c = t[2], ab = mid[0], bc = mid[1], ca = mid[2];
            fine.insert(fine.end(), {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}});
            fine_place.push_back({p.base, {p.corner[0], mid_bary[0], mid_bary[2]}});
            fine_place.push_back({p.base, {mid_bary[0], p.corner[1], mid_bary[1]}});
            fine_place.push_back({p.base, {mid_bary[2], mid_bary[1], p.corner[2]}});
            fine_place.push_back({p.base, {mid_bary[0], mid_bary[1], mid_bary[2]}});
        }
        out.faces.push_back(std::move(fine));
        out.vertex_count.push_back(next);
        place = std::move(fine_place);
    }
    return out;
}

geo::Mesh SemiRegularMesh::level_mesh(std::uint32_t j) const {
    if (j > levels()) throw geo::InputError("semi-regular remesh: no level " + std::to_string(j));
    if (positions.size() != vertex_count.back())
        throw geo::InputError("semi-regular remesh: " + std::to_string(positions.size()) + " positions for " +
                              std::to_string(vertex_count.back()) + " vertices (not mapped yet?)");
    geo::Mesh m;
    m.positions.assign(positions.begin(), positions.begin() + vertex_count[j]);
    m.triangles = faces[j];
    return m;
}

}  // namespace gimg::passes

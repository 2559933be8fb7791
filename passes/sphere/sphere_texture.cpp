// Spherical coordinates as texture coordinates, with the seam cut open for rendering.
#include "gimg/passes/sphere.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/error.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gimg::passes {

geo::Mesh spherical_texture_mesh(const geo::Mesh& mesh, const std::vector<glm::dvec3>& sphere) {
    if (sphere.size() != mesh.vertex_count())
        throw geo::InputError("sphere map has " + std::to_string(sphere.size()) + " points for " +
                              std::to_string(mesh.vertex_count()) + " vertices");
    constexpr double two_pi = 2.0 * std::numbers::pi;
    geo::Mesh out;
    out.positions = mesh.positions;
    out.texcoords.resize(mesh.vertex_count());
    for (std::size_t v = 0; v < sphere.size(); ++v) {
        const glm::dvec3& y = sphere[v];
        double longitude = std::atan2(y.x, y.z);
        if (longitude < 0.0) longitude += two_pi;
        const double colatitude = std::acos(std::clamp(y.y, -1.0, 1.0));
        out.texcoords[v] = {longitude / two_pi, colatitude / two_pi};
    }
    if (mesh.has_normals()) out.normals = mesh.normals;
    std::vector<std::uint32_t> shifted(mesh.vertex_count(), geo::kInvalidIndex);
    out.triangles = mesh.triangles;
    for (glm::uvec3& t : out.triangles) {
        const double u[3] = {out.texcoords[t.x].x, out.texcoords[t.y].x, out.texcoords[t.z].x};
        if (std::max({u[0], u[1], u[2]}) - std::min({u[0], u[1], u[2]}) <= 0.5) continue;
        for (int k = 0; k < 3; ++k) {
            if (u[k] >= 0.5) continue;
            std::uint32_t& copy = shifted[t[k]];
            if (copy == geo::kInvalidIndex) {
                copy = std::uint32_t(out.positions.size());
                out.positions.push_back(mesh.positions[t[k]]);
                out.texcoords.push_back(out.texcoords[t[k]] + glm::dvec2(1.0, 0.0));
                if (mesh.has_normals()) out.normals.push_back(mesh.normals[t[k]]);
            }
            t[k] = copy;
        }
    }
    return out;
}

}  // namespace gimg::passes

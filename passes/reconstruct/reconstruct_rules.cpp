#include "reconstruct_rules.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"

#include <glm/geometric.hpp>

#include <cmath>

namespace gimg::passes::detail {

BlockTriangles block_triangles(bool diagonal_ad, bool faces_plus) {
    // Corners a = 0, b = 1, c = 2, d = 3; (a, b, d) and (a, d, c), or (a, b, c) and (b, d, c),
    // all with normal along cross(du, dv); the other winding reverses each.
    BlockTriangles t = diagonal_ad ? BlockTriangles{{{0, 1, 3}, {0, 3, 2}}} : BlockTriangles{{{0, 1, 2}, {1, 3, 2}}};
    if (!faces_plus)
        for (auto& tri : t.corner) std::swap(tri[1], tri[2]);
    return t;
}

std::size_t full_blocks(const std::vector<std::uint8_t>& covered, std::uint32_t width, std::uint32_t height,
                        bool wrap) {
    std::size_t n = 0;
    for (std::uint32_t v = 0; v + 1 < height; ++v)
        for (std::uint32_t u = 0; u < (wrap ? width : width - 1); ++u) {
            const std::uint32_t u1 = (u + 1) % width;
            n += covered[std::size_t(v) * width + u] && covered[std::size_t(v) * width + u1] &&
                 covered[std::size_t(v + 1) * width + u] && covered[std::size_t(v + 1) * width + u1];
        }
    return n;
}

void check_reconstructible(std::uint32_t width, std::uint32_t height, std::uint32_t lod) {
    if (width < 2 || height < 2) throw geo::InputError("a geometry image needs at least 2x2 pixels to make triangles");
    if (lod > 16) throw geo::InputError("--lod " + std::to_string(lod) + " is more reductions than any image allows");
    const std::uint32_t step = 1u << lod;
    if (width % step != 0 || height % step != 0 || width / step < 2 || height / step < 2)
        throw geo::InputError("a " + std::to_string(width) + "x" + std::to_string(height) +
                              " image cannot be reduced " + std::to_string(lod) + " times (both sides must divide by " +
                              std::to_string(step) + " and stay at least 2)");
}

void add_caps(geo::Mesh& mesh, const CylinderImage& image, const CylinderFrame& frame) {
    // One fan per end: the topmost (bottommost) valid pixel of every column, joined around the
    // axis to a new vertex at their mean. Only when every column reaches that end, else there is
    // no loop to close. The ring's vertices are the grid's own (vertex index = the pixel's place
    // among the valid pixels), so the caps share their edges with the grid.
    std::vector<std::uint32_t> vertex_of(image.covered.size(), 0);
    std::uint32_t next_vertex = 0;
    for (std::size_t i = 0; i < image.covered.size(); ++i)
        if (image.covered[i]) vertex_of[i] = next_vertex++;
    const auto dirs = cylinder_directions(image.width);
    for (const bool top : {true, false}) {
        std::vector<std::uint32_t> ring;
        glm::dvec3 centre{0.0};
        for (std::uint32_t u = 0; u < image.width; ++u) {
            for (std::uint32_t k = 0; k < image.height; ++k) {
                const std::uint32_t v = top ? k : image.height - 1 - k;
                const std::size_t i = image.index(u, v);
                if (!image.covered[i]) continue;
                const double d = image.distance[i], y = 1.0 - (double(v) + 0.5) / double(image.height);
                centre += glm::dvec3(d * dirs[u][0], y, d * dirs[u][1]);
                ring.push_back(vertex_of[i]);
                break;
            }
            if (ring.size() != u + 1) break;
        }
        if (ring.size() != image.width) continue;
        centre /= double(ring.size());
        const auto middle = std::uint32_t(mesh.positions.size());
        mesh.positions.push_back(glm::dvec3(glm::vec3(frame.to_model(centre))));
        // Increasing theta runs clockwise seen from +y, so (centre, next, this) faces up.
        for (std::uint32_t u = 0; u < image.width; ++u) {
            const std::uint32_t here = ring[u], next = ring[(u + 1) % image.width];
            mesh.triangles.push_back(top ? glm::uvec3{middle, next, here} : glm::uvec3{middle, here, next});
        }
    }
}

void finish_mesh(geo::Mesh& mesh) {
    mesh.normals = geo::vertex_normals(mesh);
    for (auto& n : mesh.normals)
        if (glm::dot(n, n) == 0.0) n = {0.0, 1.0, 0.0};  // a vertex in no face still needs one
}

}  // namespace gimg::passes::detail

namespace gimg::passes {

void check_rebuilt_surface(const geo::Mesh& rebuilt, const std::string& image, const std::string& more_pixels) {
    if (rebuilt.face_count() == 0) throw geo::InputError(image + " rebuilds no face; " + more_pixels);
    double area = 0.0;
    for (double a : geo::face_areas(rebuilt)) area += a;
    if (!(area > 0.0))
        throw geo::InputError(
            image + " rebuilds only faces of no area: the model is flat, and the cylinder's rays only graze it");
}

}  // namespace gimg::passes

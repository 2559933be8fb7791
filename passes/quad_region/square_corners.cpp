// Corners for trying a region out: a square around the mesh's flattest vertex.
#include "gimg/passes/quad_region.h"

#include "gimg/geometry/curvature.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <utility>

namespace gimg::passes {

std::array<std::uint32_t, 4> flattest_square_corners(const QuadRegionCutter& cutter, double side) {
    const geo::Mesh& mesh = cutter.mesh();
    const geo::MeshAdjacency& adj = cutter.adjacency();
    const geo::VertexCurvature k = geo::compute_curvature(mesh, adj);
    const std::vector<glm::dvec3> normals = geo::vertex_normals(mesh);
    const double half = 0.5 * side * mesh.bounds().diagonal();
    std::uint32_t centre = geo::kInvalidIndex;
    double best = 1e300;
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
        if (!k.interior[v]) continue;
        double sum = k.principal_square_sum[v];
        for (std::uint32_t w : adj.neighbors(v)) sum += k.principal_square_sum[w];
        if (sum < best) best = sum, centre = v;
    }
    if (centre == geo::kInvalidIndex) throw geo::InputError("automatic corners: the mesh has no interior vertex");
    const glm::dvec3 n = normals[centre], c = mesh.positions[centre];
    const glm::dvec3 e1 =
        glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 e2 = glm::cross(n, e1);
    // Corners on the centre's own piece of the mesh (teapot: 32 pieces).
    std::vector<std::uint8_t> reached(mesh.vertex_count(), 0);
    std::vector<std::uint32_t> stack{centre};
    reached[centre] = 1;
    while (!stack.empty()) {
        const std::uint32_t v = stack.back();
        stack.pop_back();
        for (std::uint32_t w : adj.neighbors(v))
            if (!reached[w]) reached[w] = 1, stack.push_back(w);
    }
    const auto square = [&](double half_side) {
        std::array<std::uint32_t, 4> corners{};
        const double signs[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (int i = 0; i < 4; ++i) {
            const glm::dvec3 target = c + half_side * (signs[i][0] * e1 + signs[i][1] * e2);
            double nearest = 1e300;
            for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
                if (reached[v] && glm::dot(normals[v], n) > 0.0 && glm::distance(mesh.positions[v], target) < nearest)
                    nearest = glm::distance(mesh.positions[v], target), corners[i] = v;
        }
        return corners;
    };
    const auto area = [](const geo::Mesh& m) {
        const std::vector<double> a = geo::face_areas(m);
        return std::accumulate(a.begin(), a.end(), 0.0);
    };
    // A square whose sides cannot be cut to a disk (they cross, or run round a handle or a hole:
    // elephant's, turbine's and knot1's at 0.2 diagonals) gives way to one of half the side, up to
    // four times.
    std::string first_failure;
    for (int halving = 0; halving <= 4; ++halving) {
        std::array<std::uint32_t, 4> corners = square(half / double(1 << halving));
        try {
            // Where the square is wider than the part it sits on (camel's head at 0.25), the sides
            // run round that part and their left is the rest of the mesh: camel's body, which the
            // map squeezes into a point. The square is the smaller side, so a region of more than
            // half the mesh's area is taken the other way round, where that cuts (on a disk the
            // other way round reaches the boundary).
            const QuadRegion region = cutter.cut(corners, false);
            if (area(region.mesh) > 0.5 * area(mesh)) {
                std::array<std::uint32_t, 4> other = corners;
                std::swap(other[1], other[3]);
                try {
                    (void)cutter.cut(other, false);
                    return other;
                } catch (const geo::InputError&) {}
            }
            return corners;
        } catch (const geo::InputError& e) {
            if (first_failure.empty()) first_failure = e.what();
        }
    }
    char sides[96];
    std::snprintf(sides, sizeof sides, "%g to %g diagonals around the flattest vertex (%u)", side, side / 16.0, centre);
    char at[32];
    std::snprintf(at, sizeof at, "%g", side);
    throw geo::InputError(std::string("automatic corners: no square of side ") + sides + " cuts a disk region (at " +
                          at + ": " + first_failure + "); give the corners, --corners A,B,C,D");
}

}  // namespace gimg::passes

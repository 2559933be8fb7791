// The CPU reference of grid reconstruction (reconstruct_rules.h): pixel order for vertices, block
// order for triangles, as the GPU path's prefix sums produce them.
#include "gimg/passes/reconstruct.h"

#include "gimg/geometry/error.h"

#include "reconstruct_rules.h"

#include <algorithm>
#include <cmath>

namespace gimg::passes {

namespace {

// Points and validity per pixel, and each block's jump measure.
struct Grid {
    std::uint32_t width = 0, height = 0;
    bool wrap = false;
    std::vector<glm::vec3> points;
    std::vector<std::uint8_t> valid;
};

glm::vec3 cylinder_point(double d, const std::array<double, 2>& dir, double y, const CylinderFrame& f) {
    const double q0 = d * dir[0] - f.translation.x, q1 = y - f.translation.y, q2 = d * dir[1] - f.translation.z;
    // R^T q: column r of R^T is row r of R; glm stores R column-major, so R[c][r] is row r, column c.
    const double x = f.rotation[0][0] * q0 + f.rotation[0][1] * q1 + f.rotation[0][2] * q2;
    const double yy = f.rotation[1][0] * q0 + f.rotation[1][1] * q1 + f.rotation[1][2] * q2;
    const double z = f.rotation[2][0] * q0 + f.rotation[2][1] * q1 + f.rotation[2][2] * q2;
    return glm::vec3(float(x / f.scale), float(yy / f.scale), float(z / f.scale));
}

double squared(const glm::vec3& a, const glm::vec3& b) {
    const double x = double(a.x) - double(b.x), y = double(a.y) - double(b.y), z = double(a.z) - double(b.z);
    return x * x + y * y + z * z;
}

// Triangles of every block the jump test lets through, in block order.
template <class Jump, class FacesPlus>
geo::Mesh mesh_from_grid(const Grid& g, Jump&& jump_ok, FacesPlus&& faces_plus, ReconstructStats* stats) {
    geo::Mesh mesh;
    std::vector<std::uint32_t> vertex(g.points.size(), 0);
    for (std::size_t i = 0; i < g.points.size(); ++i) {
        if (!g.valid[i]) continue;
        vertex[i] = std::uint32_t(mesh.positions.size());
        mesh.positions.push_back(glm::dvec3(g.points[i]));
    }
    const std::uint32_t blocks_per_row = g.wrap ? g.width : g.width - 1;
    std::size_t holes = 0;
    for (std::uint32_t v = 0; v + 1 < g.height; ++v)
        for (std::uint32_t u = 0; u < blocks_per_row; ++u) {
            const std::uint32_t u1 = (u + 1) % g.width;
            std::size_t c[4] = {std::size_t(v) * g.width + u, std::size_t(v) * g.width + u1,
                                std::size_t(v + 1) * g.width + u, std::size_t(v + 1) * g.width + u1};
            if (!(g.valid[c[0]] && g.valid[c[1]] && g.valid[c[2]] && g.valid[c[3]])) continue;
            if (!jump_ok(c)) {
                ++holes;
                continue;
            }
            const bool ad = squared(g.points[c[0]], g.points[c[3]]) <= squared(g.points[c[1]], g.points[c[2]]);
            const detail::BlockTriangles t = detail::block_triangles(ad, faces_plus(c));
            for (const auto& tri : t.corner)
                mesh.triangles.push_back({vertex[c[tri[0]]], vertex[c[tri[1]]], vertex[c[tri[2]]]});
        }
    if (stats) stats->holes = holes;
    return mesh;
}

}  // namespace

float default_cylinder_threshold(const CylinderImage& image) {
    std::vector<float> magnitudes;
    for (std::size_t i = 0; i < image.covered.size(); ++i)
        if (image.covered[i]) magnitudes.push_back(std::abs(image.distance[i]));
    if (magnitudes.empty() || image.width == 0 || image.height == 0) return std::numeric_limits<float>::infinity();
    std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2, magnitudes.end());
    const double median = magnitudes[magnitudes.size() / 2];
    const double pitch = std::max(2.0 * 3.14159265358979323846 * median / image.width, 1.0 / image.height);
    return float(6.0 * pitch);
}

geo::Mesh reconstruct_cpu(const CylinderImage& input, const CylinderFrame& frame, const ReconstructOptions& options,
                          ReconstructStats* stats) {
    detail::check_reconstructible(input.width, input.height, options.lod);
    const CylinderImage image = lod_reduce(input, options.lod);
    const float threshold = options.threshold ? *options.threshold : default_cylinder_threshold(image);
    Grid g{image.width, image.height, true, std::vector<glm::vec3>(image.distance.size()), image.covered};
    const auto dirs = cylinder_directions(image.width);
    for (std::uint32_t v = 0; v < image.height; ++v) {
        const double y = 1.0 - (double(v) + 0.5) / double(image.height);
        for (std::uint32_t u = 0; u < image.width; ++u) {
            const std::size_t i = image.index(u, v);
            if (image.covered[i]) g.points[i] = cylinder_point(image.distance[i], dirs[u], y, frame);
        }
    }
    auto jump_ok = [&](std::size_t c[4]) {
        double lo = image.distance[c[0]], hi = lo;
        for (int k = 1; k < 4; ++k)
            lo = std::min(lo, double(image.distance[c[k]])), hi = std::max(hi, double(image.distance[c[k]]));
        return hi - lo <= double(threshold);
    };
    auto faces_plus = [&](std::size_t c[4]) {
        return (double(image.distance[c[0]]) + double(image.distance[c[1]])) +
                   (double(image.distance[c[2]]) + double(image.distance[c[3]])) >=
               0.0;
    };
    geo::Mesh mesh = mesh_from_grid(g, jump_ok, faces_plus, stats);
    if (options.fill_caps) detail::add_caps(mesh, image, frame);
    detail::finish_mesh(mesh);
    if (stats) stats->width = image.width, stats->height = image.height, stats->threshold = threshold;
    return mesh;
}

geo::Mesh reconstruct_cpu(const PositionImage& input, const ReconstructOptions& options, ReconstructStats* stats) {
    detail::check_reconstructible(input.width, input.height, options.lod);
    if (options.fill_caps) throw geo::InputError("--fill-caps is for cylindrical images");
    const PositionImage image = lod_reduce(input, options.lod);
    const float threshold = options.threshold ? *options.threshold : std::numeric_limits<float>::infinity();
    Grid g{image.width, image.height, false, std::vector<glm::vec3>(image.covered.size()), image.covered};
    for (std::size_t i = 0; i < g.points.size(); ++i)
        g.points[i] = {image.xyz[3 * i], image.xyz[3 * i + 1], image.xyz[3 * i + 2]};
    const double t2 = double(threshold) * double(threshold);
    auto jump_ok = [&](std::size_t c[4]) {
        double worst = 0.0;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b) worst = std::max(worst, squared(g.points[c[a]], g.points[c[b]]));
        return worst <= t2;
    };
    geo::Mesh mesh = mesh_from_grid(
        g, jump_ok, [](std::size_t*) { return false; }, stats);
    detail::finish_mesh(mesh);
    if (stats) stats->width = image.width, stats->height = image.height, stats->threshold = threshold;
    return mesh;
}

}  // namespace gimg::passes

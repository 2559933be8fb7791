// The silhouette baseline: 7 silhouettes per model by the renderer, Zernike magnitudes per view.
#include "gimg/passes/render.h"
#include "gimg/passes/retrieval.h"

#include "gimg/geometry/error.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>

namespace gimg::passes {

namespace {

constexpr int kOrder = 10;
constexpr std::uint32_t kSide = 128;
constexpr std::size_t kViews = 7;  // 3 axes, then the diagonals (1,1,1), (1,1,-1), (1,-1,1), (1,-1,-1)

std::size_t moments_per_view() {
    std::size_t n = 0;
    for (int order = 0; order <= kOrder; ++order)
        for (int m = order % 2; m <= order; m += 2) ++n;
    return n;
}

}  // namespace

std::vector<float> zernike_magnitudes(const std::vector<std::uint8_t>& inside, std::uint32_t width,
                                      std::uint32_t height) {
    double cx = 0.0, cy = 0.0, count = 0.0;
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x)
            if (inside[std::size_t(y) * width + x]) cx += x, cy += y, count += 1.0;
    std::vector<float> out(moments_per_view(), 0.0f);
    if (count == 0.0) return out;
    cx /= count, cy /= count;
    double radius = 0.0;
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x)
            if (inside[std::size_t(y) * width + x]) radius = std::max(radius, std::hypot(x - cx, y - cy));
    radius += 0.5;  // the farthest pixel's far edge
    // The radial polynomials' coefficients, once: (-1)^s (n - s)! / (s! ((n + m) / 2 - s)! ((n - m) / 2 - s)!).
    static const auto coefficient = [] {
        std::array<std::array<std::array<double, kOrder / 2 + 1>, kOrder + 1>, kOrder + 1> c{};
        for (int n = 0; n <= kOrder; ++n)
            for (int m = n % 2; m <= n; m += 2)
                for (int s = 0; s <= (n - m) / 2; ++s)
                    c[n][m][s] =
                        (s % 2 ? -1.0 : 1.0) * std::tgamma(n - s + 1) /
                        (std::tgamma(s + 1) * std::tgamma((n + m) / 2 - s + 1) * std::tgamma((n - m) / 2 - s + 1));
        return c;
    }();
    std::vector<std::complex<double>> z(out.size());
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x) {
            if (!inside[std::size_t(y) * width + x]) continue;
            const double rho = std::hypot(x - cx, y - cy) / radius, theta = std::atan2(y - cy, x - cx);
            std::size_t k = 0;
            for (int n = 0; n <= kOrder; ++n)
                for (int m = n % 2; m <= n; m += 2, ++k) {
                    double r = 0.0;  // the radial polynomial R_nm(rho)
                    for (int s = 0; s <= (n - m) / 2; ++s) r += coefficient[n][m][s] * std::pow(rho, n - 2 * s);
                    z[k] += r * std::polar(1.0, -m * theta);
                }
        }
    const double z00 = std::abs(z[0]);
    for (std::size_t k = 0; k < z.size(); ++k) out[k] = float(std::abs(z[k]) / z00);
    return out;
}

std::vector<float> silhouette_descriptor(Context& ctx, const geo::Mesh& mesh) {
    if (mesh.face_count() == 0) throw geo::InputError("silhouettes: the mesh has no faces");
    geo::Mesh framed = mesh;  // in its principal frame
    const CylinderFrame frame = fit_cylinder_frame(mesh);
    for (auto& p : framed.positions) p = frame.rotation * p;
    framed.normals.clear();
    // The principal axes are x (second), y (main), z (third) of the frame.
    const std::array<glm::dvec3, kViews> lines{glm::dvec3(1, 0, 0),  glm::dvec3(0, 1, 0),  glm::dvec3(0, 0, 1),
                                               glm::dvec3(1, 1, 1),  glm::dvec3(1, 1, -1), glm::dvec3(1, -1, 1),
                                               glm::dvec3(1, -1, -1)};
    RenderOptions options;
    options.width = options.height = kSide;
    options.supersample = 2;
    std::vector<float> out;
    for (const glm::dvec3& line : lines) {
        const glm::dvec3 d = glm::normalize(line);
        options.view.elevation_deg = glm::degrees(std::asin(std::clamp(d.y, -1.0, 1.0)));
        options.view.azimuth_deg = glm::degrees(std::atan2(d.x, d.z));
        const geo::RgbaImage picture = render_mesh(ctx, framed, options);
        std::vector<std::uint8_t> inside(std::size_t(kSide) * kSide);
        for (std::size_t i = 0; i < inside.size(); ++i) inside[i] = picture.pixels[4 * i + 3] >= 128;
        const std::vector<float> z = zernike_magnitudes(inside, kSide, kSide);
        out.insert(out.end(), z.begin(), z.end());
    }
    return out;
}

double silhouette_distance(const std::vector<float>& a, const std::vector<float>& b) {
    const std::size_t per = moments_per_view();
    if (a.size() != kViews * per || b.size() != a.size())
        throw geo::InputError("silhouettes: descriptors of the wrong size");
    auto view_l1 = [&](std::size_t va, std::size_t vb) {
        double s = 0.0;
        for (std::size_t k = 0; k < per; ++k) s += std::abs(double(a[va * per + k]) - double(b[vb * per + k]));
        return s;
    };
    double axes = 0.0;
    for (std::size_t v = 0; v < 3; ++v) axes += view_l1(v, v);
    // Flipping the signs of two axes permutes the diagonal lines: (x, y), (x, z), (y, z) flips.
    constexpr std::array<std::array<std::size_t, 4>, 4> perms{{{3, 4, 5, 6}, {6, 5, 4, 3}, {5, 6, 3, 4}, {4, 3, 6, 5}}};
    double best = std::numeric_limits<double>::infinity();
    for (const auto& p : perms) {
        double s = 0.0;
        for (std::size_t i = 0; i < 4; ++i) s += view_l1(3 + i, p[i]);
        best = std::min(best, s);
    }
    return axes + best;
}

}  // namespace gimg::passes

// Retrieval features: the cylindrical image of each model (GPU Z-buffer, batched) and its cubic
// reduction (the thesis, 5.2: a low pass, then decimation).
#include "gimg/passes/retrieval.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/surface_sampling.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace gimg::passes {

namespace {

// Keys's cubic convolution kernel (a = -0.5).
double keys(double x) {
    x = std::abs(x);
    constexpr double a = -0.5;
    if (x <= 1.0) return ((a + 2.0) * x - (a + 3.0)) * x * x + 1.0;
    if (x < 2.0) return ((a * x - 5.0 * a) * x + 8.0 * a) * x - 4.0 * a;
    return 0.0;
}

// For each of `out` samples over `in` inputs (factor f = in / out): the inputs it weighs and their
// normalised weights; `wrap` makes the axis circular, else indices are clamped.
std::vector<std::vector<std::pair<std::uint32_t, double>>> taps(std::uint32_t in, std::uint32_t out, bool wrap) {
    const double f = double(in) / double(out);
    std::vector<std::vector<std::pair<std::uint32_t, double>>> all(out);
    for (std::uint32_t o = 0; o < out; ++o) {
        const double centre = (o + 0.5) * f - 0.5;
        double sum = 0.0;
        for (long k = long(std::floor(centre - 2.0 * f)); k <= long(std::ceil(centre + 2.0 * f)); ++k) {
            const double w = keys((double(k) - centre) / f);
            if (w == 0.0) continue;
            const long i = wrap ? ((k % long(in)) + long(in)) % long(in) : std::clamp(k, 0L, long(in) - 1);
            all[o].push_back({std::uint32_t(i), w});
            sum += w;
        }
        for (auto& [i, w] : all[o]) w /= sum;
    }
    return all;
}

}  // namespace

std::vector<float> reduce_cylinder_image(const CylinderImage& image, std::uint32_t reduced) {
    if (reduced == 0 || image.width % reduced != 0 || image.height % reduced != 0)
        throw geo::InputError("retrieval: a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                              " image does not reduce to " + std::to_string(reduced) + "x" + std::to_string(reduced));
    const auto across = taps(image.width, reduced, true), down = taps(image.height, reduced, false);
    std::vector<double> rows(std::size_t(image.height) * reduced, 0.0);  // reduced in u first
    for (std::uint32_t v = 0; v < image.height; ++v)
        for (std::uint32_t o = 0; o < reduced; ++o) {
            double s = 0.0;
            for (const auto& [u, w] : across[o]) {
                const std::size_t i = image.index(u, v);
                s += w * (image.covered[i] ? double(image.distance[i]) : 0.0);
            }
            rows[std::size_t(v) * reduced + o] = s;
        }
    std::vector<float> out(std::size_t(reduced) * reduced);
    for (std::uint32_t o = 0; o < reduced; ++o)
        for (std::uint32_t u = 0; u < reduced; ++u) {
            double s = 0.0;
            for (const auto& [v, w] : down[o]) s += w * rows[std::size_t(v) * reduced + u];
            out[std::size_t(o) * reduced + u] = float(s);
        }
    return out;
}

std::vector<std::vector<float>> cylinder_features(Context& ctx, const std::vector<geo::Mesh>& meshes,
                                                  const RetrievalOptions& options) {
    CylinderZBuffer zbuffer(ctx, options.size, options.size);
    std::vector<CylinderZBuffer::Job> jobs;
    for (const geo::Mesh& mesh : meshes)
        jobs.push_back({zbuffer.add_mesh(make_cylinder_mesh(mesh, fit_cylinder_frame(mesh))), kIdentityTransform});
    const std::vector<CylinderImage> images = zbuffer.project(jobs);
    std::vector<std::vector<float>> out;
    out.reserve(images.size());
    for (const CylinderImage& image : images) out.push_back(reduce_cylinder_image(image, options.reduced));
    return out;
}

std::vector<float> d2_histogram(const geo::Mesh& mesh, std::uint32_t bins) {
    geo::SurfaceSamplingOptions sampling;
    sampling.sample_count = 1024;
    const std::vector<glm::dvec3> p = geo::sample_surface(mesh, sampling);
    std::vector<double> d;
    d.reserve(p.size() * (p.size() - 1) / 2);
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j) d.push_back(glm::distance(p[i], p[j]));
    std::vector<float> h(bins, 0.0f);
    if (d.empty()) return h;
    double mean = 0.0;
    for (double x : d) mean += x;
    mean /= double(d.size());
    if (!(mean > 0.0)) return h;
    for (double x : d) h[std::min<std::size_t>(bins - 1, std::size_t(x / (3.0 * mean) * bins))] += 1.0f;
    for (float& v : h) v /= float(d.size());
    return h;
}

}  // namespace gimg::passes

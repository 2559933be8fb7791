#include "gimg/geometry/surface_sampling.h"

#include "gimg/geometry/normals.h"

#include <algorithm>
#include <cmath>

namespace gimg::geo {

namespace {

std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// Uniform double in [0, 1) from the top 53 bits.
double unit_double(std::uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }

// R2 sequence steps: 1/g and 1/g^2, g the plastic number (the real root of x^3 = x + 1).
constexpr double kPlastic = 1.32471795724474602596;
constexpr double kR2StepU = 1.0 / kPlastic;
constexpr double kR2StepV = 1.0 / (kPlastic * kPlastic);

}  // namespace

std::size_t resolve_sample_count(const SurfaceSamplingOptions& options, std::size_t faces) {
    if (options.sample_count > 0) return options.sample_count;
    return std::max(options.min_samples, options.samples_per_face * faces);
}

std::vector<std::uint32_t> face_sample_counts(const std::vector<double>& face_areas, std::size_t total,
                                              std::uint64_t seed) {
    std::vector<std::uint32_t> counts(face_areas.size(), 0);
    double area_sum = 0.0;
    for (double a : face_areas) area_sum += a;
    if (!(area_sum > 0.0) || total == 0) return counts;
    const double u = unit_double(splitmix64(seed ^ 0xa0761d6478bd642full));
    const double scale = double(total) / area_sum;
    std::size_t last_with_area = 0;
    for (std::size_t f = 0; f < face_areas.size(); ++f)
        if (face_areas[f] > 0.0) last_with_area = f;
    double cumulative = 0.0;
    double previous = 0.0;  // floor(0 + u)
    for (std::size_t f = 0; f <= last_with_area; ++f) {
        cumulative += face_areas[f] * scale;
        // The last face with area closes the sum exactly, so rounding in the running sum never
        // loses or adds a sample.
        const double c = f == last_with_area ? double(total) : std::min(cumulative, double(total));
        const double next = std::floor(c + u);
        counts[f] = static_cast<std::uint32_t>(next - previous);
        previous = next;
    }
    return counts;
}

glm::dvec3 triangle_sample(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, std::uint32_t face,
                           std::uint32_t i, std::uint64_t seed) {
    const std::uint64_t h = splitmix64(seed ^ splitmix64(face));
    const double shift_u = unit_double(h), shift_v = unit_double(splitmix64(h));
    double s = shift_u + kR2StepU * double(i + 1);
    double t = shift_v + kR2StepV * double(i + 1);
    s -= std::floor(s);
    t -= std::floor(t);
    if (s + t > 1.0) {
        s = 1.0 - s;
        t = 1.0 - t;
    }
    return a + s * (b - a) + t * (c - a);
}

std::vector<glm::dvec3> sample_surface(const Mesh& mesh, const SurfaceSamplingOptions& options) {
    const std::vector<std::uint32_t> counts =
        face_sample_counts(face_areas(mesh), resolve_sample_count(options, mesh.face_count()), options.seed);
    std::vector<glm::dvec3> samples;
    std::size_t n = 0;
    for (std::uint32_t c : counts) n += c;
    samples.reserve(n);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        for (std::uint32_t i = 0; i < counts[f]; ++i)
            samples.push_back(triangle_sample(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z],
                                              static_cast<std::uint32_t>(f), i, options.seed));
    }
    return samples;
}

}  // namespace gimg::geo

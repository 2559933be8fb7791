#include "gimg/geometry/surface_distance.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/geometry/parallel_for.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <vector>

namespace gimg::geo {

namespace {

// Faces per work chunk. Fixed (never derived from the thread count) so that the per-chunk
// partial sums, combined in chunk order, give the same bits on any machine.
constexpr std::size_t kFacesPerChunk = 256;
constexpr std::size_t kVerticesPerChunk = 4096;

struct Partial {
    double sum = 0.0;
    double sum_squares = 0.0;
    double max = 0.0;
    std::size_t count = 0;
};

double total_area(const std::vector<double>& areas) {
    double s = 0.0;
    for (double a : areas) s += a;
    return s;
}

// Largest distance from the vertices of `from` that some face uses.
double vertex_max_distance(const Mesh& from, const TriangleBvh& to, unsigned threads) {
    std::vector<std::uint8_t> used(from.vertex_count(), 0);
    for (const glm::uvec3& t : from.triangles) used[t.x] = used[t.y] = used[t.z] = 1;
    std::vector<double> chunk_max(chunk_count(from.vertex_count(), kVerticesPerChunk), 0.0);
    parallel_for_chunks(
        from.vertex_count(), kVerticesPerChunk,
        [&](std::size_t chunk, std::size_t begin, std::size_t end) {
            double m = 0.0;
            std::uint32_t hint = kInvalidIndex;
            for (std::size_t v = begin; v < end; ++v) {
                if (!used[v]) continue;
                const ClosestPointResult r =
                    to.closest_point(from.positions[v], std::numeric_limits<double>::infinity(), hint);
                hint = r.face;
                m = std::max(m, r.distance);
            }
            chunk_max[chunk] = m;
        },
        threads);
    double m = 0.0;
    for (double x : chunk_max) m = std::max(m, x);
    return m;
}

}  // namespace

DistanceStats one_sided_distance(const Mesh& from, const TriangleBvh& to, const SurfaceDistanceOptions& options) {
    const std::vector<double> areas = face_areas(from);
    if (!(total_area(areas) > 0.0)) throw InputError("surface distance: the sampled mesh has no area");
    if (to.empty()) throw InputError("surface distance: the target mesh has no faces");
    const std::uint64_t seed = options.sampling.seed;
    const std::vector<std::uint32_t> counts =
        face_sample_counts(areas, resolve_sample_count(options.sampling, from.face_count()), seed);

    std::vector<Partial> partials(chunk_count(from.face_count(), kFacesPerChunk));
    std::mutex progress_lock;
    std::size_t chunks_done = 0;
    parallel_for_chunks(
        from.face_count(), kFacesPerChunk,
        [&](std::size_t chunk, std::size_t begin, std::size_t end) {
            Partial p;
            // Consecutive samples lie on the same or a neighbouring face, so the previous answer
            // is a tight first guess that lets the BVH search prune almost everything.
            std::uint32_t hint = kInvalidIndex;
            for (std::size_t f = begin; f < end; ++f) {
                const glm::uvec3& t = from.triangles[f];
                for (std::uint32_t i = 0; i < counts[f]; ++i) {
                    const glm::dvec3 q = triangle_sample(from.positions[t.x], from.positions[t.y], from.positions[t.z],
                                                         static_cast<std::uint32_t>(f), i, seed);
                    const ClosestPointResult r = to.closest_point(q, std::numeric_limits<double>::infinity(), hint);
                    hint = r.face;
                    p.sum += r.distance;
                    p.sum_squares += r.distance * r.distance;
                    p.max = std::max(p.max, r.distance);
                    ++p.count;
                }
            }
            partials[chunk] = p;
            if (options.progress) {
                const std::lock_guard<std::mutex> lock(progress_lock);
                options.progress(double(++chunks_done) / double(partials.size()));
            }
        },
        options.threads);

    Partial total;
    for (const Partial& p : partials) {
        total.sum += p.sum;
        total.sum_squares += p.sum_squares;
        total.max = std::max(total.max, p.max);
        total.count += p.count;
    }
    DistanceStats s;
    s.samples = total.count;
    s.mean = total.count ? total.sum / double(total.count) : 0.0;
    s.rms = total.count ? std::sqrt(total.sum_squares / double(total.count)) : 0.0;
    s.max = std::max(total.max, vertex_max_distance(from, to, options.threads));
    return s;
}

SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, const SurfaceDistanceOptions& options) {
    if (!(total_area(face_areas(a)) > 0.0)) throw InputError("surface distance: mesh A has no area");
    if (!(total_area(face_areas(b)) > 0.0)) throw InputError("surface distance: mesh B has no area");
    BvhBuildOptions build;
    build.threads = options.threads;
    const TriangleBvh bvh_a(a, build), bvh_b(b, build);

    SurfaceDistance d;
    SurfaceDistanceOptions half = options;
    if (options.progress) half.progress = [&](double done) { options.progress(0.5 * done); };
    d.a_to_b = one_sided_distance(a, bvh_b, half);
    if (options.progress) half.progress = [&](double done) { options.progress(0.5 + 0.5 * done); };
    d.b_to_a = one_sided_distance(b, bvh_a, half);
    d.bbox_diagonal = a.bounds().diagonal();

    // Union of both sample sets: recover the sums from mean and RMS.
    const double na = double(d.a_to_b.samples), nb = double(d.b_to_a.samples);
    const double sum = d.a_to_b.mean * na + d.b_to_a.mean * nb;
    const double sum_squares = d.a_to_b.rms * d.a_to_b.rms * na + d.b_to_a.rms * d.b_to_a.rms * nb;
    d.symmetric.samples = d.a_to_b.samples + d.b_to_a.samples;
    d.symmetric.mean = sum / (na + nb);
    d.symmetric.rms = std::sqrt(sum_squares / (na + nb));
    d.symmetric.max = std::max(d.a_to_b.max, d.b_to_a.max);
    return d;
}

}  // namespace gimg::geo

// Retrieval features: the cylindrical image of each model (GPU Z-buffer, batched) and its cubic
// reduction (the thesis, 5.2: a low pass, then decimation).
#include "gimg/passes/retrieval.h"

#include "gimg/engine/graph.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/geometry/pca.h"
#include "gimg/geometry/surface_sampling.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "retrieval/reduce_comp.h"

#include <algorithm>
#include <bit>
#include <span>
#include <cmath>
#include <string>
#include <utility>

namespace gimg::passes {

namespace {

const Spirv kReduce = GIMG_SPIRV(gimg_spv_retrieval_reduce_comp);

struct ReducePush {
    std::uint32_t size, reduced, count, taps;
};

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

PanoramaFrame panorama_frame(const geo::Mesh& mesh) {
    // compute_pca_alignment gives a mesh with no area (a flat strip) the identity about its vertices'
    // centroid, so it still gets images, as the thesis's descriptor gives it one.
    const geo::PcaAlignment pca = geo::compute_pca_alignment(mesh, geo::PcaWeighting::SurfaceArea);
    std::vector<glm::dvec3> q(mesh.positions.size());
    for (std::size_t i = 0; i < q.size(); ++i) q[i] = pca.transform.apply_point(mesh.positions[i]);
    // The surface's mean distance from the centroid, by area (each triangle at its centroid); the
    // triangles counted alike when none has area.
    double area = 0.0, mean = 0.0, plain = 0.0;
    for (const auto& t : mesh.triangles) {
        const double a = 0.5 * glm::length(glm::cross(q[t[1]] - q[t[0]], q[t[2]] - q[t[0]]));
        const double d = glm::length((q[t[0]] + q[t[1]] + q[t[2]]) / 3.0);
        area += a, mean += a * d, plain += d;
    }
    mean = area > 0.0 ? mean / area : mesh.triangles.empty() ? 0.0 : plain / double(mesh.triangles.size());
    if (!std::isfinite(mean)) throw geo::InputError("retrieval: the mesh's coordinates are not finite");
    if (!(mean > 0.0)) mean = 1.0;
    PanoramaFrame out;
    out.mesh.positions.reserve(3 * q.size());
    for (auto& p : q) {
        p /= mean;
        out.mesh.positions.insert(out.mesh.positions.end(), {float(p.x), float(p.y), float(p.z)});
    }
    out.mesh.triangles.reserve(3 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) out.mesh.triangles.insert(out.mesh.triangles.end(), {t.x, t.y, t.z});
    // Per principal axis, the farthest used vertex from it (squared) and along it: a stray point
    // does not count.
    std::vector<char> used(q.size(), 0);
    for (const auto& t : mesh.triangles) used[t.x] = used[t.y] = used[t.z] = 1;
    glm::dvec3 off_axis(0.0), along(0.0);  // off_axis[i]: squared distance from axis i
    for (std::size_t i = 0; i < q.size(); ++i) {
        if (!used[i]) continue;
        const glm::dvec3 p(out.mesh.positions[3 * i], out.mesh.positions[3 * i + 1], out.mesh.positions[3 * i + 2]);
        off_axis = glm::max(off_axis, glm::dvec3(p.y * p.y + p.z * p.z, p.x * p.x + p.z * p.z, p.x * p.x + p.y * p.y));
        along = glm::max(along, glm::abs(p));
    }
    // (u, axis, v) right-handed (cyclic permutations of the principal frame), so faces keep facing out.
    const glm::dvec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a) {
        const int i = a == 0 ? 1 : a == 1 ? 0 : 2;
        const glm::dvec3 axis = e[i];
        const glm::dvec3 u = a == 0 ? e[0] : a == 1 ? e[2] : e[1], v = glm::cross(u, axis);
        const double r = std::max(3.0, 1.001 * std::sqrt(off_axis[i])), h = std::max(r, 1.001 * along[i]);
        out.transforms[a] = {float(u.x / r),          float(u.y / r),          float(u.z / r),          0.0f,
                             float(0.5 * axis.x / h), float(0.5 * axis.y / h), float(0.5 * axis.z / h), 0.5f,
                             float(v.x / r),          float(v.y / r),          float(v.z / r),          0.0f};
    }
    return out;
}

namespace {

std::vector<std::vector<float>> panorama_features(Context& ctx, const std::vector<geo::Mesh>& meshes) {
    std::vector<CylinderMesh> frames(meshes.size());
    std::vector<std::array<CylinderTransform, 3>> transforms(meshes.size());
    geo::parallel_for_chunks(meshes.size(), 1, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t m = begin; m < end; ++m) {
            PanoramaFrame f = panorama_frame(meshes[m]);
            frames[m] = std::move(f.mesh);
            transforms[m] = f.transforms;
        }
    });
    CylinderZBuffer zbuffer(ctx, kPanoramaWidth, kPanoramaHeight);
    std::size_t all_vertices = 0, all_faces = 0;
    for (const CylinderMesh& c : frames) all_vertices += c.positions.size() / 3, all_faces += c.face_count();
    zbuffer.reserve(all_vertices, all_faces);
    const std::vector<std::uint32_t> ids = zbuffer.add_meshes(frames);  // one upload a model, three images
    frames = {};
    constexpr std::size_t batch = 85;  // models an execution: 255 images
    std::vector<std::vector<float>> out(meshes.size());
    for (std::size_t begin = 0; begin < ids.size(); begin += batch) {
        const std::size_t end = std::min(ids.size(), begin + batch);
        std::vector<CylinderZBuffer::Job> jobs;
        for (std::size_t m = begin; m < end; ++m)
            for (std::size_t a = 0; a < 3; ++a) jobs.push_back({ids[m], transforms[m][a]});
        const std::vector<CylinderImage> images = zbuffer.project(jobs);
        const std::size_t pixels = std::size_t(kPanoramaWidth) * kPanoramaHeight;
        for (std::size_t k = 0; k < images.size(); ++k) {
            auto& f = out[begin + k / 3];
            f.resize(3 * pixels);
            for (std::size_t i = 0; i < pixels; ++i)  // surfaces seen through the axis: 0
                f[k % 3 * pixels + i] =
                    images[k].covered[i] && images[k].distance[i] > 0.0f ? images[k].distance[i] : 0.0f;
        }
    }
    return out;
}

}  // namespace

std::vector<std::vector<float>> cylinder_features(Context& ctx, const std::vector<geo::Mesh>& meshes,
                                                  const RetrievalOptions& options) {
    if (options.descriptor == RetrievalDescriptor::Panorama) return panorama_features(ctx, meshes);
    const std::uint32_t n = options.size, r = options.reduced;
    if (r == 0 || n % r != 0)
        throw geo::InputError("retrieval: a " + std::to_string(n) + " image does not reduce to " + std::to_string(r));
    // The taps of reduce_cylinder_image, padded to one count per output; an index travels as float bits.
    const auto u_taps = taps(n, r, true), v_taps = taps(n, r, false);
    std::uint32_t width = 0;
    for (const auto* t : {&u_taps, &v_taps})
        for (const auto& list : *t) width = std::max(width, std::uint32_t(list.size()));
    auto table = [&](const std::vector<std::vector<std::pair<std::uint32_t, double>>>& t) {
        std::vector<float> out(2 * std::size_t(r) * width, 0.0f);
        for (std::uint32_t o = 0; o < r; ++o)
            for (std::size_t k = 0; k < t[o].size(); ++k) {
                out[2 * (o * width + k)] = std::bit_cast<float>(t[o][k].first);
                out[2 * (o * width + k) + 1] = float(t[o][k].second);
            }
        return out;
    };
    Buffer tu = upload_buffer(ctx, table(u_taps), "retrieval taps u"),
           tv = upload_buffer(ctx, table(v_taps), "retrieval taps v");

    if (options.cylinders != 1 && options.cylinders != 3) throw geo::InputError("retrieval: 1 or 3 cylinders");
    // Each model's frame and cylinder meshes on every core, then one upload of them all.
    const std::uint32_t per_model = options.cylinders;
    std::vector<CylinderMesh> cylinder_meshes(meshes.size() * per_model);
    geo::parallel_for_chunks(meshes.size(), 1, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t m = begin; m < end; ++m) {
            const geo::Mesh& mesh = meshes[m];
            const CylinderFrame frame = fit_cylinder_frame(mesh);
            cylinder_meshes[m * per_model] = make_cylinder_mesh(mesh, frame);
            // With 3 cylinders: the model in its principal frame, each of the two other axes turned
            // onto the cylinder's (a cyclic permutation: no mirror), then centred and scaled into it.
            for (std::uint32_t turn = 1; turn < per_model; ++turn) {
                geo::Mesh turned = mesh;
                for (auto& p : turned.positions) {
                    const glm::dvec3 q = frame.rotation * p;
                    p = turn == 1 ? glm::dvec3(q.y, q.z, q.x) : glm::dvec3(q.z, q.x, q.y);
                }
                cylinder_meshes[m * per_model + turn] = make_cylinder_mesh(turned, fit_cylinder_frame(turned, false));
            }
        }
    });
    CylinderZBuffer zbuffer(ctx, n, n);
    std::size_t all_vertices = 0, all_faces = 0;
    for (const CylinderMesh& c : cylinder_meshes) all_vertices += c.positions.size() / 3, all_faces += c.face_count();
    zbuffer.reserve(all_vertices, all_faces);
    std::vector<CylinderZBuffer::Job> jobs;
    std::vector<std::size_t> job_faces;
    const std::vector<std::uint32_t> ids = zbuffer.add_meshes(cylinder_meshes);
    for (std::size_t k = 0; k < ids.size(); ++k) {
        jobs.push_back({ids[k], kIdentityTransform});
        job_faces.push_back(cylinder_meshes[k].face_count());
    }
    cylinder_meshes = {};
    std::vector<std::vector<float>> out;
    out.reserve(meshes.size());
    // Graphs of at most 256 images and 1M faces, well inside what one execution holds.
    constexpr std::size_t kBatchImages = 256, kBatchFaces = 1u << 20;
    for (std::size_t begin = 0, end = 0; begin < jobs.size(); begin = end) {
        std::size_t faces = 0;
        end = begin;
        while (end < jobs.size() && end - begin < kBatchImages &&
               (end == begin || faces + job_faces[end] <= kBatchFaces))
            faces += job_faces[end++];
        const auto count = std::uint32_t(end - begin);
        Graph g(ctx);
        const CylinderImagesHandle images =
            add_cylinder(g, zbuffer, std::span(jobs).subspan(begin, count), "retrieval images");
        auto features = g.create_buffer({VkDeviceSize(count) * r * r * 4, "retrieval features"});
        auto taps_u = g.import_buffer(tu), taps_v = g.import_buffer(tv);
        const ReducePush push{n, r, count, width};
        g.add_compute_pass(
            "retrieval: reduce",
            [&](PassBuilder& b) {
                b.read(images.distance, Access::ComputeRead);
                b.read(taps_u, Access::ComputeRead);
                b.read(taps_v, Access::ComputeRead);
                features = b.write(features, Access::ComputeWrite);
            },
            [=, d = images.distance](Cmd& c) {
                c.dispatch_threads(kReduce, {r, r, count}, {d, taps_u, taps_v, features}, push);
            });
        g.export_buffer(features, Access::TransferSrc);
        Plan plan = g.compile();
        plan.execute();
        std::vector<float> all(std::size_t(count) * r * r);
        ctx.download(plan.buffer(features), all.data(), all.size() * 4);
        for (std::uint32_t k = 0; k < count; ++k) {
            if ((begin + k) % options.cylinders == 0) out.emplace_back();
            out.back().insert(out.back().end(), all.begin() + std::ptrdiff_t(k) * r * r,
                              all.begin() + std::ptrdiff_t(k + 1) * r * r);
        }
    }
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

// One hierarchy level's relaxation on the render graph, and its CPU twin.
#include "sphere/harmonic/relaxation.h"

#include "sphere/sphere_steps.h"
#include "gimg/engine/texel_array.h"

#include "gimg/engine/graph.h"
#include "gimg/geometry/parallel_for.h"
#include "gimg/passes/primitives.h"

#include "sphere/map_stats_comp.h"
#include "sphere/recentre_comp.h"
#include "sphere/relax_comp.h"

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <cstring>
#include <span>

namespace gimg::passes::detail {

namespace {

const Spirv kRelax = GIMG_SPIRV(gimg_spv_sphere_relax_comp);
const Spirv kLevelStats = GIMG_SPIRV(gimg_spv_sphere_map_stats_comp);
const Spirv kRecentre = GIMG_SPIRV(gimg_spv_sphere_recentre_comp);

// The shaders' layouts (shaders/sphere/sphere_common.glsl): storage images, one texel an element.
// A point is two RGBA32UI texels, (x, y) and (z, 0) as doubles: byte for byte one dvec4 a point.
Image upload_points(Context& ctx, const std::vector<glm::dvec3>& y, const std::string& name) {
    std::vector<glm::dvec2> texels(2 * y.size(), glm::dvec2(0.0));
    for (std::size_t i = 0; i < y.size(); ++i) {
        texels[2 * i] = {y[i].x, y[i].y};
        texels[2 * i + 1] = {y[i].z, 0.0};
    }
    return upload_texel_array(ctx, std::move(texels), Format::RGBA32U, name);
}

// The fans' spokes, (neighbour, 0, weight as a double), one RGBA32UI texel a spoke.
Image upload_spokes(Context& ctx, const RelaxationMesh& level) {
    std::vector<glm::uvec4> texels(level.ring.size());
    for (std::size_t k = 0; k < texels.size(); ++k) {
        std::uint64_t bits;
        std::memcpy(&bits, &level.ring_weights[k], sizeof bits);
        texels[k] = {level.ring[k], 0u, std::uint32_t(bits), std::uint32_t(bits >> 32)};
    }
    return upload_texel_array(ctx, std::move(texels), Format::RGBA32U, "sphere spokes");
}

MapStats stats_from_sums(std::span<const double> sums, std::size_t vertex_count) {
    MapStats stats;
    stats.centroid = glm::dvec3(sums[0], sums[1], sums[2]) / double(vertex_count);
    stats.energy = sums[3];
    stats.flips = std::size_t(sums[4]);
    stats.kernel_failures = std::size_t(sums[5]);
    return stats;
}

}  // namespace

RelaxCheck relax_and_check_cpu(const RelaxationMesh& level, std::vector<glm::dvec3>& y, std::uint32_t iterations,
                               bool uniform_weights, double recentre_scale) {
    for (std::uint32_t i = 0; i < iterations; ++i) relax_sweep_cpu(level, y, uniform_weights);
    RelaxCheck check;
    check.relaxed = map_stats_cpu(level, y);
    const glm::dvec3 a = recentring_point(check.relaxed.centroid, recentre_scale);
    std::vector<glm::dvec3> moved(y.size());
    for (std::size_t v = 0; v < y.size(); ++v) moved[v] = moebius_move(y[v], a);
    check.recentred = map_stats_cpu(level, moved);
    check.recentre_kept = check.recentred.kernel_failures <= check.relaxed.kernel_failures &&
                          check.recentred.flips <= check.relaxed.flips;
    if (check.recentre_kept) y = std::move(moved);
    return check;
}

CentreRun centre_mass_cpu(const RelaxationMesh& level, std::vector<glm::dvec3>& y, const MapStats& now,
                          double tolerance, std::size_t max_steps) {
    CentreRun run;
    run.stats = now;
    std::vector<glm::dvec3> moved = y;
    glm::dvec3 centroid = run.stats.centroid;
    // Each step in chunks on the CPU's threads, their sums added in chunk order (relaxation_mesh.h).
    std::vector<glm::dvec3> sums(geo::chunk_count(moved.size(), kLevelChunk));
    while (run.steps < max_steps && glm::length(centroid) > tolerance) {
        const glm::dvec3 a = recentring_point(centroid, kRecentreScale);
        geo::parallel_for_chunks(moved.size(), kLevelChunk, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
            glm::dvec3 sum(0.0);
            for (std::size_t v = begin; v < end; ++v) {
                moved[v] = moebius_move(moved[v], a);
                sum += moved[v];
            }
            sums[chunk] = sum;
        });
        centroid = glm::dvec3(0.0);
        for (const glm::dvec3& sum : sums) centroid += sum;
        centroid /= double(moved.size());
        ++run.steps;
    }
    if (run.steps == 0) return run;
    const MapStats after = map_stats_cpu(level, moved);
    run.kept = after.flips <= run.stats.flips && after.kernel_failures <= run.stats.kernel_failures;
    if (!run.kept) return run;
    y = std::move(moved);
    run.stats = after;
    return run;
}

GpuRelaxation::GpuRelaxation(Context& ctx, const RelaxationMesh& level, const std::vector<glm::dvec3>& y)
    : ctx_(ctx), level_(level) {
    ctx.batch_uploads([&] {  // one submission for the five
        points_[0] = upload_points(ctx, y, "sphere points A");
        points_[1] = upload_points(ctx, y, "sphere points B");
        ring_offsets_ = upload_texel_array(ctx, level.ring_offsets, Format::R32U, "sphere ring offsets");
        spokes_ = upload_spokes(ctx, level);
        members_ = upload_texel_array(ctx, level.colour_members, Format::R32U, "sphere colour members");
    });
    sums_relaxed_ = ctx.create_buffer({6 * sizeof(double), "sphere sums (relaxed)"}, MemoryUsage::Readback);
    sums_recentred_ = ctx.create_buffer({6 * sizeof(double), "sphere sums (recentred)"}, MemoryUsage::Readback);
    control_ = ctx.create_buffer({sizeof(double), "sphere recentre scale"}, MemoryUsage::Upload);
}

Plan& GpuRelaxation::plan_for(std::uint32_t iterations, bool uniform_weights) {
    auto& slot = plans_[{iterations, uniform_weights, current_}];
    if (slot) return *slot;
    const auto n = std::uint32_t(level_.vertex_count());
    Graph g(ctx_);
    auto points = g.import_image(points_[current_]);
    auto moved = g.import_image(points_[1 - current_]);
    auto offsets = g.import_image(ring_offsets_);
    auto spokes = g.import_image(spokes_);
    auto members = g.import_image(members_);
    auto control = g.import_buffer(control_);
    struct RelaxPush {
        std::uint32_t first, count, uniform_weights;
    };
    g.add_loop(iterations, [&] {
        for (std::size_t c = 0; c < level_.colour_count(); ++c) {
            const RelaxPush push{level_.colour_offsets[c], level_.colour_offsets[c + 1] - level_.colour_offsets[c],
                                 uniform_weights ? 1u : 0u};
            g.add_compute_pass(
                "relax colour " + std::to_string(c),
                [&](PassBuilder& b) {
                    for (ImageHandle h : {offsets, spokes, members}) b.read(h, Access::ComputeRead);
                    points = b.write(points, Access::ComputeReadWrite);
                },
                [=](Cmd& cmd) {
                    cmd.dispatch_threads(kRelax, {push.count}, {points, offsets, spokes, members}, push);
                });
        }
    });
    auto reduce_stats = [&](ImageHandle of, Buffer& sums_buffer, const std::string& name) {
        auto terms = g.create_buffer({VkDeviceSize(n) * 6 * sizeof(double), name + " terms"});
        g.add_compute_pass(
            name,
            [&](PassBuilder& b) {
                for (ImageHandle h : {of, offsets, spokes}) b.read(h, Access::ComputeRead);
                terms = b.write(terms, Access::ComputeWrite);
            },
            [=](Cmd& cmd) {
                cmd.dispatch_threads(kLevelStats, {n}, {of, offsets, spokes, terms}, n);
            });
        auto sums = add_reduce_sum_f64(g, terms, g.import_buffer(sums_buffer), n, 6, name + " sum");
        return sums;
    };
    auto sums = reduce_stats(points, sums_relaxed_, "sphere stats");
    g.add_compute_pass(
        "sphere recentre",
        [&](PassBuilder& b) {
            b.read(points, Access::ComputeRead);
            b.read(sums, Access::ComputeRead);
            b.read(control, Access::ComputeRead);
            moved = b.write(moved, Access::ComputeWrite);
        },
        [=](Cmd& cmd) {
            cmd.dispatch_threads(kRecentre, {n}, {points, sums, control, moved}, n);
        });
    auto sums_moved = reduce_stats(moved, sums_recentred_, "sphere stats recentred");
    g.export_buffer(sums, Access::HostRead);
    g.export_buffer(sums_moved, Access::HostRead);
    g.export_image(points, Access::ComputeReadWrite);
    g.export_image(moved, Access::ComputeReadWrite);
    slot = std::make_unique<Plan>(g.compile());
    return *slot;
}

RelaxCheck GpuRelaxation::run(std::uint32_t iterations, bool uniform_weights) {
    Plan& plan = plan_for(iterations, uniform_weights);
    control_.mapped_as<double>()[0] = recentre_scale_;
    plan.execute({.wait = true, .timestamps = timestamps_});
    last_gpu_ms_ = timestamps_ ? plan.total_gpu_ms() : 0.0;
    RelaxCheck check;
    check.relaxed = stats_from_sums(sums_relaxed_.mapped_as<double>(), level_.vertex_count());
    check.recentred = stats_from_sums(sums_recentred_.mapped_as<double>(), level_.vertex_count());
    check.recentre_kept = check.recentred.kernel_failures <= check.relaxed.kernel_failures &&
                          check.recentred.flips <= check.relaxed.flips;
    if (check.recentre_kept) {
        current_ = 1 - current_;
        recentre_scale_ = kRecentreScale;
    } else {
        recentre_scale_ *= 0.5;
    }
    return check;
}

std::vector<glm::dvec3> GpuRelaxation::positions() {
    const std::vector<std::byte> bytes = ctx_.download(points_[current_]);
    std::vector<glm::dvec3> y(level_.vertex_count());
    for (std::size_t i = 0; i < y.size(); ++i) {
        double p[4];
        std::memcpy(p, bytes.data() + 4 * sizeof(double) * i, sizeof p);  // (x, y), (z, 0): one dvec4
        y[i] = {p[0], p[1], p[2]};
    }
    return y;
}

}  // namespace gimg::passes::detail

// One hierarchy level's relaxation on the render graph, and its CPU twin.
#include "sphere_relax.h"

#include "sphere_steps.h"
#include "upload_vector.h"

#include "gimg/engine/graph.h"
#include "gimg/passes/primitives.h"

#include "sphere/level_stats_comp.h"
#include "sphere/recentre_comp.h"
#include "sphere/relax_comp.h"

#include <glm/geometric.hpp>

#include <span>

namespace gimg::passes::detail {

namespace {

const Spirv kRelax = GIMG_SPIRV(gimg_spv_sphere_relax_comp);
const Spirv kLevelStats = GIMG_SPIRV(gimg_spv_sphere_level_stats_comp);
const Spirv kRecentre = GIMG_SPIRV(gimg_spv_sphere_recentre_comp);

// The shaders' layout: one dvec4 per point (w unused), shaders/sphere/sphere_common.glsl.
std::vector<double> flatten(const std::vector<glm::dvec3>& y) {
    std::vector<double> flat(4 * y.size(), 0.0);
    for (std::size_t i = 0; i < y.size(); ++i)
        for (int k = 0; k < 3; ++k) flat[4 * i + k] = y[i][k];
    return flat;
}

LevelStats stats_from_sums(std::span<const double> sums, std::size_t vertex_count) {
    LevelStats stats;
    stats.centroid = glm::dvec3(sums[0], sums[1], sums[2]) / double(vertex_count);
    stats.energy = sums[3];
    stats.flips = std::size_t(sums[4]);
    stats.kernel_failures = std::size_t(sums[5]);
    return stats;
}

}  // namespace

RelaxCheck relax_and_check_cpu(const SphereLevel& level, std::vector<glm::dvec3>& y, std::uint32_t iterations,
                               bool uniform_weights, double recentre_scale) {
    for (std::uint32_t i = 0; i < iterations; ++i) relax_sweep_cpu(level, y, uniform_weights);
    RelaxCheck check;
    check.relaxed = level_stats_cpu(level, y);
    const glm::dvec3 a = recentring_point(check.relaxed.centroid, recentre_scale);
    std::vector<glm::dvec3> moved(y.size());
    for (std::size_t v = 0; v < y.size(); ++v) moved[v] = moebius_move(y[v], a);
    check.recentred = level_stats_cpu(level, moved);
    check.recentre_kept = check.recentred.kernel_failures <= check.relaxed.kernel_failures &&
                          check.recentred.flips <= check.relaxed.flips;
    if (check.recentre_kept) y = std::move(moved);
    return check;
}

CentreRun centre_mass_cpu(const SphereLevel& level, std::vector<glm::dvec3>& y, const LevelStats& now, double tolerance,
                          std::size_t max_steps) {
    CentreRun run;
    run.stats = now;
    std::vector<glm::dvec3> moved = y;
    glm::dvec3 centroid = run.stats.centroid;
    while (run.steps < max_steps && glm::length(centroid) > tolerance) {
        const glm::dvec3 a = recentring_point(centroid, kRecentreScale);
        centroid = glm::dvec3(0.0);
        for (glm::dvec3& p : moved) {
            p = moebius_move(p, a);
            centroid += p;
        }
        centroid /= double(moved.size());
        ++run.steps;
    }
    if (run.steps == 0) return run;
    const LevelStats after = level_stats_cpu(level, moved);
    run.kept = after.flips <= run.stats.flips && after.kernel_failures <= run.stats.kernel_failures;
    if (!run.kept) return run;
    y = std::move(moved);
    run.stats = after;
    return run;
}

GpuSphereRelaxation::GpuSphereRelaxation(Context& ctx, const SphereLevel& level, const std::vector<glm::dvec3>& y)
    : ctx_(ctx), level_(level) {
    const std::vector<double> flat = flatten(y);
    points_[0] = upload_vector(ctx, flat, "sphere points A");
    points_[1] = upload_vector(ctx, flat, "sphere points B");
    ring_offsets_ = upload_vector(ctx, level.ring_offsets, "sphere ring offsets");
    ring_ = upload_vector(ctx, level.ring, "sphere rings");
    ring_weights_ = upload_vector(ctx, level.ring_weights, "sphere ring weights");
    members_ = upload_vector(ctx, level.colour_members, "sphere colour members");
    sums_relaxed_ = ctx.create_buffer({6 * sizeof(double), "sphere sums (relaxed)"}, MemoryUsage::Readback);
    sums_recentred_ = ctx.create_buffer({6 * sizeof(double), "sphere sums (recentred)"}, MemoryUsage::Readback);
    control_ = ctx.create_buffer({sizeof(double), "sphere recentre scale"}, MemoryUsage::Upload);
}

Plan& GpuSphereRelaxation::plan_for(std::uint32_t iterations, bool uniform_weights) {
    auto& slot = plans_[{iterations, uniform_weights, current_}];
    if (slot) return *slot;
    const auto n = std::uint32_t(level_.vertex_count());
    Graph g(ctx_);
    auto points = g.import_buffer(points_[current_]);
    auto moved = g.import_buffer(points_[1 - current_]);
    auto offsets = g.import_buffer(ring_offsets_);
    auto ring = g.import_buffer(ring_);
    auto weights = g.import_buffer(ring_weights_);
    auto members = g.import_buffer(members_);
    auto control = g.import_buffer(control_);
    struct RelaxPush {
        std::uint32_t first, count, uniform_weights;
    };
    g.add_loop(iterations, [&] {
        for (std::size_t c = 0; c < level_.colour_count(); ++c) {
            const RelaxPush push{level_.colour_offsets[c], level_.colour_offsets[c + 1] - level_.colour_offsets[c],
                                 uniform_weights ? 1u : 0u};
            g.add_compute_pass("relax colour " + std::to_string(c), [&](PassBuilder& b) {
                b.read(offsets, Access::ComputeRead);
                b.read(ring, Access::ComputeRead);
                b.read(weights, Access::ComputeRead);
                b.read(members, Access::ComputeRead);
                points = b.write(points, Access::ComputeReadWrite);
            }, [=](Cmd& cmd) {
                cmd.dispatch_threads(kRelax, {push.count}, {points, offsets, ring, weights, members}, push);
            });
        }
    });
    auto reduce_stats = [&](BufferHandle of, Buffer& sums_buffer, const std::string& name) {
        auto terms = g.create_buffer({VkDeviceSize(n) * 6 * sizeof(double), name + " terms"});
        g.add_compute_pass(name, [&](PassBuilder& b) {
            for (BufferHandle h : {of, offsets, ring, weights}) b.read(h, Access::ComputeRead);
            terms = b.write(terms, Access::ComputeWrite);
        }, [=](Cmd& cmd) { cmd.dispatch_threads(kLevelStats, {n}, {of, offsets, ring, weights, terms}, n); });
        auto sums = add_reduce_sum_f64(g, terms, g.import_buffer(sums_buffer), n, 6, name + " sum");
        return sums;
    };
    auto sums = reduce_stats(points, sums_relaxed_, "sphere stats");
    g.add_compute_pass("sphere recentre", [&](PassBuilder& b) {
        b.read(points, Access::ComputeRead);
        b.read(sums, Access::ComputeRead);
        b.read(control, Access::ComputeRead);
        moved = b.write(moved, Access::ComputeWrite);
    }, [=](Cmd& cmd) { cmd.dispatch_threads(kRecentre, {n}, {points, sums, control, moved}, n); });
    auto sums_moved = reduce_stats(moved, sums_recentred_, "sphere stats recentred");
    g.export_buffer(sums, Access::HostRead);
    g.export_buffer(sums_moved, Access::HostRead);
    g.export_buffer(points, Access::ComputeReadWrite);
    g.export_buffer(moved, Access::ComputeReadWrite);
    slot = std::make_unique<Plan>(g.compile());
    return *slot;
}

RelaxCheck GpuSphereRelaxation::run(std::uint32_t iterations, bool uniform_weights) {
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

std::vector<glm::dvec3> GpuSphereRelaxation::positions() {
    const std::vector<double> flat = ctx_.download<double>(points_[current_]);
    std::vector<glm::dvec3> y(level_.vertex_count());
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = {flat[4 * i], flat[4 * i + 1], flat[4 * i + 2]};
    return y;
}

}  // namespace gimg::passes::detail

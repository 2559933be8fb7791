// Conjugate gradients for the planar polish on the render graph, and its CPU twin.
#include "plane_cg.h"

#include "upload_vector.h"

#include "gimg/engine/graph.h"
#include "gimg/passes/primitives.h"

#include "sphere/cg_apply_comp.h"
#include "sphere/cg_direction_comp.h"
#include "sphere/cg_step_comp.h"

#include <glm/geometric.hpp>

namespace gimg::passes::detail {

namespace {

const Spirv kApply = GIMG_SPIRV(gimg_spv_sphere_cg_apply_comp);
const Spirv kStep = GIMG_SPIRV(gimg_spv_sphere_cg_step_comp);
const Spirv kDirection = GIMG_SPIRV(gimg_spv_sphere_cg_direction_comp);

// Row i of A p, in cg_apply.comp's order.
glm::dvec2 apply_row(const PlaneProblem& problem, const std::vector<glm::dvec2>& p, std::size_t i) {
    glm::dvec2 sum = problem.diagonal[i] * p[i];
    for (std::uint32_t k = problem.row_offsets[i]; k < problem.row_offsets[i + 1]; ++k)
        sum += problem.values[k] * p[problem.columns[k]];
    return sum;
}

}  // namespace

PlaneCgState start_plane_cg(const PlaneProblem& problem) {
    PlaneCgState state;
    const std::size_t m = problem.rows();
    state.x = problem.start;
    state.r.resize(m);
    state.p.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
        state.r[i] = problem.rhs[i] - apply_row(problem, state.x, i);
        state.p[i] = state.r[i] / problem.diagonal[i];
        state.rz += glm::dot(state.r[i], state.p[i]);
        state.rz_rhs += glm::dot(problem.rhs[i], problem.rhs[i] / problem.diagonal[i]);
    }
    return state;
}

void plane_cg_cpu(const PlaneProblem& problem, PlaneCgState& state, std::uint32_t iterations) {
    const std::size_t m = problem.rows();
    std::vector<glm::dvec2> q(m);
    for (std::uint32_t it = 0; it < iterations; ++it) {
        double pq = 0.0;
        for (std::size_t i = 0; i < m; ++i) {
            q[i] = apply_row(problem, state.p, i);
            pq += glm::dot(state.p[i], q[i]);
        }
        const double alpha = pq > 0.0 ? state.rz / pq : 0.0;
        double rz = 0.0;
        for (std::size_t i = 0; i < m; ++i) {
            state.x[i] += alpha * state.p[i];
            state.r[i] -= alpha * q[i];
            rz += glm::dot(state.r[i], state.r[i] / problem.diagonal[i]);
        }
        const double beta = state.rz > 0.0 ? rz / state.rz : 0.0;
        for (std::size_t i = 0; i < m; ++i) state.p[i] = state.r[i] / problem.diagonal[i] + beta * state.p[i];
        state.rz = rz;
    }
}

GpuPlaneCg::GpuPlaneCg(Context& ctx, const PlaneProblem& problem) : ctx_(ctx), rows_(std::uint32_t(problem.rows())) {
    const PlaneCgState start = start_plane_cg(problem);
    rz_rhs_ = start.rz_rhs;
    offsets_ = upload_vector(ctx, problem.row_offsets, "plane cg row offsets");
    columns_ = upload_vector(ctx, problem.columns, "plane cg columns");
    values_ = upload_vector(ctx, problem.values, "plane cg values");
    diagonal_ = upload_vector(ctx, problem.diagonal, "plane cg diagonal");
    x_ = upload_vector(ctx, start.x, "plane cg x");
    r_ = upload_vector(ctx, start.r, "plane cg r");
    p_ = upload_vector(ctx, start.p, "plane cg p");
    q_ = ctx.create_buffer({VkDeviceSize(std::max<std::uint32_t>(rows_, 1)) * sizeof(glm::dvec2), "plane cg q"});
    rz_[0] = ctx.create_buffer({sizeof(double), "plane cg r.z"}, MemoryUsage::Readback);
    rz_[1] = ctx.create_buffer({sizeof(double), "plane cg r.z (odd iterations)"});
    pq_ = ctx.create_buffer({sizeof(double), "plane cg p.q"});
    ctx.upload(rz_[0], std::span<const double>(&start.rz, 1));
}

Plan& GpuPlaneCg::plan_for(std::uint32_t iterations) {
    auto& slot = plans_[iterations];
    if (slot) return *slot;
    Graph g(ctx_);
    auto offsets = g.import_buffer(offsets_);
    auto columns = g.import_buffer(columns_);
    auto values = g.import_buffer(values_);
    auto diagonal = g.import_buffer(diagonal_);
    auto x = g.import_buffer(x_);
    auto r = g.import_buffer(r_);
    auto p = g.import_buffer(p_);
    auto q = g.import_buffer(q_);
    BufferHandle rz[2] = {g.import_buffer(rz_[0]), g.import_buffer(rz_[1])};
    auto pq = g.import_buffer(pq_);
    auto terms = g.create_buffer({VkDeviceSize(std::max<std::uint32_t>(rows_, 1)) * sizeof(double), "plane cg terms"});
    const std::uint32_t rows = rows_;
    g.add_loop(iterations / 2, [&] {
        for (int half = 0; half < 2; ++half) {
            const BufferHandle rz_old = rz[half];
            const std::string suffix = half ? " (odd)" : " (even)";
            g.add_compute_pass("plane cg apply" + suffix, [&](PassBuilder& b) {
                for (BufferHandle h : {p, offsets, columns, values, diagonal}) b.read(h, Access::ComputeRead);
                q = b.write(q, Access::ComputeWrite);
                terms = b.write(terms, Access::ComputeWrite);
            }, [=](Cmd& cmd) { cmd.dispatch_threads(kApply, {rows}, {p, offsets, columns, values, diagonal, q, terms}, rows); });
            pq = add_reduce_sum_f64(g, terms, pq, rows, 1, "plane cg p.q" + suffix);
            g.add_compute_pass("plane cg step" + suffix, [&](PassBuilder& b) {
                for (BufferHandle h : {pq, rz_old, p, q, diagonal}) b.read(h, Access::ComputeRead);
                x = b.write(x, Access::ComputeReadWrite);
                r = b.write(r, Access::ComputeReadWrite);
                terms = b.write(terms, Access::ComputeWrite);
            }, [=](Cmd& cmd) { cmd.dispatch_threads(kStep, {rows}, {pq, rz_old, p, q, diagonal, x, r, terms}, rows); });
            const BufferHandle rz_new = rz[1 - half] = add_reduce_sum_f64(g, terms, rz[1 - half], rows, 1, "plane cg r.z" + suffix);
            g.add_compute_pass("plane cg direction" + suffix, [&](PassBuilder& b) {
                for (BufferHandle h : {rz_old, rz_new, r, diagonal}) b.read(h, Access::ComputeRead);
                p = b.write(p, Access::ComputeReadWrite);
            }, [=](Cmd& cmd) { cmd.dispatch_threads(kDirection, {rows}, {rz_old, rz_new, r, diagonal, p}, rows); });
        }
    });
    g.export_buffer(rz[0], Access::HostRead);
    for (BufferHandle h : {x, r, p, q, pq, rz[1]}) g.export_buffer(h, Access::ComputeReadWrite);
    slot = std::make_unique<Plan>(g.compile());
    return *slot;
}

double GpuPlaneCg::run(std::uint32_t iterations) {
    iterations += iterations % 2;
    if (rows_ == 0) return 0.0;
    Plan& plan = plan_for(iterations);
    plan.execute({.wait = true, .timestamps = timestamps_});
    last_gpu_ms_ = timestamps_ ? plan.total_gpu_ms() : 0.0;
    return relative_residual(ctx_.download<double>(rz_[0])[0], rz_rhs_);
}

std::vector<glm::dvec2> GpuPlaneCg::solution() {
    if (rows_ == 0) return {};
    return ctx_.download<glm::dvec2>(x_);
}

}  // namespace gimg::passes::detail

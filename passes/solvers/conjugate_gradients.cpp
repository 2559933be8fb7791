// Multigrid-preconditioned conjugate gradients for the planar polish on the render graph, and its
// CPU twin.
#include "solvers/conjugate_gradients.h"

#include "gimg/engine/graph.h"
#include "gimg/passes/primitives.h"

#include "solvers/cg_apply_comp.h"
#include "solvers/cg_direction_comp.h"
#include "solvers/cg_step_comp.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <future>

namespace gimg::passes::detail {

namespace {

const Spirv kApply = GIMG_SPIRV(gimg_spv_solvers_cg_apply_comp);
const Spirv kStep = GIMG_SPIRV(gimg_spv_solvers_cg_step_comp);
const Spirv kDirection = GIMG_SPIRV(gimg_spv_solvers_cg_direction_comp);

double dot_sum(const std::vector<glm::dvec2>& a, const std::vector<glm::dvec2>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += glm::dot(a[i], b[i]);
    return sum;
}

// r . z with r rounded to float, as the cycle sees it (its b) and its last pass sums it.
double rounded_dot_sum(const std::vector<glm::dvec2>& r, const std::vector<glm::dvec2>& z) {
    double sum = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) sum += glm::dot(glm::dvec2(glm::vec2(r[i])), z[i]);
    return sum;
}

}  // namespace

std::uint32_t iterations_to_reach(double tolerance, double before, double after, std::uint32_t iterations,
                                  std::uint32_t per_check) {
    const double rate = std::pow(after / before, 1.0 / double(iterations));
    if (!(rate > 0.0 && rate < 1.0) || !(after > tolerance)) return per_check;
    const double needed = std::ceil(std::log(tolerance / after) / std::log(rate));
    return std::clamp<std::uint32_t>(std::uint32_t(std::min(needed, double(per_check))), 1,
                                     std::max<std::uint32_t>(per_check, 1));
}

CgState start_cg(const SpdSystem& problem, const Multigrid& mg) {
    CgState state;
    const std::size_t m = problem.rows();
    state.x = problem.start;
    state.r.resize(m);
    for (std::size_t i = 0; i < m; ++i) state.r[i] = problem.rhs[i] - row_times(mg.finest(), state.x, i);
    // From zero (the harmonic start's free vertices) r is b: one cycle on the CPU, not two
    // (7-10 ms each on armadillo_loop1); else the cycle of b runs on a second thread beside r's.
    const bool from_zero =
        std::all_of(state.x.begin(), state.x.end(), [](const glm::dvec2& v) { return v == glm::dvec2(0.0); });
    std::future<double> rz_rhs;
    if (!from_zero)
        rz_rhs = std::async(std::launch::async,
                            [&] { return rounded_dot_sum(problem.rhs, apply_multigrid_cpu(mg, problem.rhs)); });
    state.p = apply_multigrid_cpu(mg, state.r);
    state.rz = rounded_dot_sum(state.r, state.p);
    state.rz_rhs = from_zero ? state.rz : rz_rhs.get();
    return state;
}

void cg_cpu(const Multigrid& mg, CgState& state, std::uint32_t iterations) {
    const std::size_t m = state.x.size();
    std::vector<glm::dvec2> q(m);
    for (std::uint32_t it = 0; it < iterations; ++it) {
        for (std::size_t i = 0; i < m; ++i) q[i] = row_times(mg.finest(), state.p, i);
        const double pq = dot_sum(state.p, q);
        const double alpha = pq > 0.0 ? state.rz / pq : 0.0;
        for (std::size_t i = 0; i < m; ++i) {
            state.x[i] += alpha * state.p[i];
            state.r[i] -= alpha * q[i];
        }
        const std::vector<glm::dvec2> z = apply_multigrid_cpu(mg, state.r);
        const double rz = rounded_dot_sum(state.r, z);
        const double beta = state.rz > 0.0 ? rz / state.rz : 0.0;
        for (std::size_t i = 0; i < m; ++i) state.p[i] = z[i] + beta * state.p[i];
        state.rz = rz;
    }
}

GpuConjugateGradients::GpuConjugateGradients(Context& ctx, const SpdSystem& problem, const Multigrid& mg)
    : ctx_(ctx), rows_(std::uint32_t(problem.rows())) {
    // The CPU start on a second thread while this one uploads the hierarchy (each 8-15 ms on
    // armadillo_loop1).
    std::future<CgState> started = std::async(std::launch::async, [&] { return start_cg(problem, mg); });
    // Every upload in one submission (a real GPU waits for each: Context::batch_uploads).
    ctx.batch_uploads([&] { upload(mg, started); });
}

void GpuConjugateGradients::upload(const Multigrid& mg, std::future<CgState>& started) {
    Context& ctx = ctx_;
    cycle_ = std::make_unique<GpuVcycle>(ctx, mg, "plane mg");
    // q = A p in double: A's entries again, in double; its rows are level 0's when there is one.
    apply_entries_ = upload_texels(ctx, entry_texels(mg.finest()), "plane cg A entries");
    if (!cycle_->has_levels()) apply_rows_ = upload_rows(ctx, mg.finest(), {}, "plane cg A");
    const CgState start = started.get();
    rz_rhs_ = start.rz_rhs;
    start_residual_ = start.relative_residual();
    x_ = upload_vector_texels(ctx, start.x, "plane cg x");
    r_ = upload_vector_texels(ctx, start.r, "plane cg r");
    p_ = upload_vector_texels(ctx, start.p, "plane cg p");
    q_ = ctx.create_image(texel_image_desc(rows_, "plane cg q"));
    rz_[0] = ctx.create_buffer({sizeof(double), "plane cg r.z"}, MemoryUsage::Readback);
    rz_[1] = ctx.create_buffer({sizeof(double), "plane cg r.z (other)"}, MemoryUsage::Readback);
    pq_ = ctx.create_buffer({sizeof(double), "plane cg p.q"});
    ctx.upload(rz_[0], std::span<const double>(&start.rz, 1));
}

Plan& GpuConjugateGradients::plan_for(std::uint32_t iterations) {
    auto& slot = plans_[{iterations, rz_index_}];
    if (slot) return *slot;
    Graph g(ctx_);
    VcycleRecorder cycle(g, *cycle_);
    struct MatrixHandles {
        ImageHandle rows, entries;
    };
    const MatrixHandles finest{cycle_->has_levels() ? cycle.finest_rows() : g.import_image(apply_rows_),
                               g.import_image(apply_entries_)};
    auto x = g.import_image(x_);
    auto r = g.import_image(r_);
    auto p = g.import_image(p_);
    auto q = g.import_image(q_);
    auto r32 = g.create_image(float_vector_desc(rows_, "plane cg r (float)"));  // the cycle's b
    auto z = g.create_image(float_vector_desc(rows_, "plane cg z"));
    BufferHandle rz[2] = {g.import_buffer(rz_[0]), g.import_buffer(rz_[1])};
    auto pq = g.import_buffer(pq_);
    auto terms = g.create_buffer({VkDeviceSize(std::max<std::uint32_t>(rows_, 1)) * sizeof(double), "plane cg terms"});
    const std::uint32_t rows = rows_;

    // One iteration whose old r.z is in rz[from] and new r.z goes to the other.
    auto add_iteration = [&](int from, const std::string& suffix) {
        const BufferHandle rz_old = rz[from];
        g.add_compute_pass(
            "plane cg apply" + suffix,
            [&](PassBuilder& b) {
                for (ImageHandle h : {p, finest.rows, finest.entries}) b.read(h, Access::ComputeRead);
                q = b.write(q, Access::ComputeWrite);
                terms = b.write(terms, Access::ComputeWrite);
            },
            [=](Cmd& cmd) {
                cmd.dispatch_threads(kApply, {rows}, {p, finest.rows, finest.entries, q, terms}, rows);
            });
        pq = add_reduce_sum_f64(g, terms, pq, rows, 1, "plane cg p.q" + suffix);
        g.add_compute_pass(
            "plane cg step" + suffix,
            [&](PassBuilder& b) {
                for (BufferHandle h : {pq, rz_old}) b.read(h, Access::ComputeRead);
                for (ImageHandle h : {p, q}) b.read(h, Access::ComputeRead);
                x = b.write(x, Access::ComputeReadWrite);
                r = b.write(r, Access::ComputeReadWrite);
                r32 = b.write(r32, Access::ComputeWrite);
            },
            [=](Cmd& cmd) {
                cmd.dispatch_threads(kStep, {rows}, {pq, rz_old, p, q, x, r, r32}, rows);
            });
        cycle.add(r32, z, terms, true, suffix);  // z = V-cycle(r), and r.z's terms
        const BufferHandle rz_new = rz[1 - from] =
            add_reduce_sum_f64(g, terms, rz[1 - from], rows, 1, "plane cg r.z" + suffix);
        g.add_compute_pass(
            "plane cg direction" + suffix,
            [&](PassBuilder& b) {
                for (BufferHandle h : {rz_old, rz_new}) b.read(h, Access::ComputeRead);
                b.read(z, Access::ComputeRead);
                p = b.write(p, Access::ComputeReadWrite);
            },
            [=](Cmd& cmd) {
                cmd.dispatch_threads(kDirection, {rows}, {rz_old, rz_new, z, p}, rows);
            });
    };
    // The loop body runs two iterations, so that r.z goes back to the buffer it came from; an odd
    // count ends with one more, and r.z is then in the other buffer.
    const int first = rz_index_;
    if (iterations >= 2) {
        g.add_loop(iterations / 2, [&] {
            add_iteration(first, " (even)");
            add_iteration(1 - first, " (odd)");
        });
    }
    if (iterations % 2) add_iteration(first, " (last)");
    const int last = (first + int(iterations % 2)) % 2;
    g.export_buffer(rz[last], Access::HostRead);
    g.export_buffer(rz[1 - last], Access::ComputeReadWrite);
    for (ImageHandle h : {x, r, p, q}) g.export_image(h, Access::ComputeReadWrite);
    g.export_buffer(pq, Access::ComputeReadWrite);
    slot = std::make_unique<Plan>(g.compile());
    return *slot;
}

double GpuConjugateGradients::run(std::uint32_t iterations) {
    if (rows_ == 0) return 0.0;
    if (iterations == 0) return relative_residual(ctx_.download<double>(rz_[rz_index_])[0], rz_rhs_);
    Plan& plan = plan_for(iterations);
    plan.execute({.wait = true, .timestamps = timestamps_});
    last_gpu_ms_ = timestamps_ ? plan.total_gpu_ms() : 0.0;
    rz_index_ = (rz_index_ + int(iterations % 2)) % 2;
    return relative_residual(ctx_.download<double>(rz_[rz_index_])[0], rz_rhs_);
}

std::vector<glm::dvec2> GpuConjugateGradients::solution() {
    if (rows_ == 0) return {};
    return download_vector_texels(ctx_, x_, rows_);
}

CgSolve solve_cg_gpu(Context& ctx, const SpdSystem& problem, const Multigrid& mg, double tolerance,
                     std::uint32_t per_check, std::size_t max_iterations, bool timestamps,
                     const std::function<void(std::size_t, double)>& progress) {
    GpuConjugateGradients cg(ctx, problem, mg);
    cg.set_timestamps(timestamps);
    CgSolve solve;
    solve.residual = cg.start_residual();
    std::uint32_t chunk = per_check;
    while (solve.iterations < max_iterations && std::isfinite(solve.residual) && solve.residual > tolerance) {
        const double before = solve.residual;
        solve.residual = cg.run(chunk);
        solve.iterations += chunk;
        chunk = iterations_to_reach(tolerance, before, solve.residual, chunk, per_check);
        solve.gpu_ms += cg.last_gpu_ms();
        if (progress) progress(solve.iterations, solve.residual);
    }
    solve.x = cg.solution();
    return solve;
}

}  // namespace gimg::passes::detail

// Multigrid-preconditioned conjugate gradients for the planar polish on the render graph, and its
// CPU twin.
#include "plane_cg.h"

#include "upload_vector.h"

#include "gimg/engine/graph.h"
#include "gimg/passes/primitives.h"

#include "sphere/cg_apply_comp.h"
#include "sphere/cg_direction_comp.h"
#include "sphere/cg_step_comp.h"
#include "sphere/mg_coarsest_comp.h"
#include "sphere/mg_postsmooth_comp.h"
#include "sphere/mg_presmooth_comp.h"
#include "sphere/mg_transfer_comp.h"

#include <glm/geometric.hpp>

namespace gimg::passes::detail {

namespace {

const Spirv kApply = GIMG_SPIRV(gimg_spv_sphere_cg_apply_comp);
const Spirv kStep = GIMG_SPIRV(gimg_spv_sphere_cg_step_comp);
const Spirv kDirection = GIMG_SPIRV(gimg_spv_sphere_cg_direction_comp);
const Spirv kPresmooth = GIMG_SPIRV(gimg_spv_sphere_mg_presmooth_comp);
const Spirv kTransfer = GIMG_SPIRV(gimg_spv_sphere_mg_transfer_comp);
const Spirv kCoarsest = GIMG_SPIRV(gimg_spv_sphere_mg_coarsest_comp);
const Spirv kPostsmooth = GIMG_SPIRV(gimg_spv_sphere_mg_postsmooth_comp);

double dot_sum(const std::vector<glm::dvec2>& a, const std::vector<glm::dvec2>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += glm::dot(a[i], b[i]);
    return sum;
}

// Push constants of the cycle's passes: the level's rows and the pass's switch (mg_transfer:
// accumulate; mg_postsmooth and mg_coarsest: write r.z's terms).
struct RowsAndSwitch {
    std::uint32_t rows;
    std::uint32_t on;
};

}  // namespace

PlaneCgState start_plane_cg(const PlaneProblem& problem, const PlaneMultigrid& mg) {
    PlaneCgState state;
    const std::size_t m = problem.rows();
    state.x = problem.start;
    state.r.resize(m);
    for (std::size_t i = 0; i < m; ++i) state.r[i] = problem.rhs[i] - row_times(mg.finest(), state.x, i);
    state.p = apply_multigrid_cpu(mg, state.r);
    state.rz = dot_sum(state.r, state.p);
    state.rz_rhs = dot_sum(problem.rhs, apply_multigrid_cpu(mg, problem.rhs));
    return state;
}

void plane_cg_cpu(const PlaneMultigrid& mg, PlaneCgState& state, std::uint32_t iterations) {
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
        const double rz = dot_sum(state.r, z);
        const double beta = state.rz > 0.0 ? rz / state.rz : 0.0;
        for (std::size_t i = 0; i < m; ++i) state.p[i] = z[i] + beta * state.p[i];
        state.rz = rz;
    }
}

GpuPlaneCg::Matrix GpuPlaneCg::upload(const CsrMatrix& m, const std::string& name) {
    return {upload_vector(ctx_, m.offsets, name + " offsets"), upload_vector(ctx_, m.columns, name + " columns"),
            upload_vector(ctx_, m.values, name + " values"), std::uint32_t(m.rows())};
}

GpuPlaneCg::GpuPlaneCg(Context& ctx, const PlaneProblem& problem, const PlaneMultigrid& mg)
    : ctx_(ctx), rows_(std::uint32_t(problem.rows())) {
    const PlaneCgState start = start_plane_cg(problem, mg);
    rz_rhs_ = start.rz_rhs;
    for (std::size_t l = 0; l < mg.levels.size(); ++l) {
        const std::string name = "plane mg level " + std::to_string(l);
        const MultigridLevel& level = mg.levels[l];
        levels_.push_back({upload(level.a, name + " A"), upload(level.prolong, name + " P"),
                           upload(level.restrict_, name + " R"), upload_vector(ctx, level.smoother, name + " smoother")});
    }
    if (levels_.empty()) finest_ = upload(mg.coarsest, "plane mg coarsest A");
    coarsest_inverse_ = upload_vector(ctx, mg.coarsest_inverse, "plane mg coarsest inverse");
    coarsest_rows_ = std::uint32_t(mg.coarsest_rows());
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
    struct MatrixHandles {
        BufferHandle offsets, columns, values;
        std::uint32_t rows;
    };
    auto import = [&](Matrix& m) {
        return MatrixHandles{g.import_buffer(m.offsets), g.import_buffer(m.columns), g.import_buffer(m.values), m.rows};
    };
    auto vector = [&](std::uint32_t rows, const std::string& name) {
        return g.create_buffer({VkDeviceSize(std::max<std::uint32_t>(rows, 1)) * sizeof(glm::dvec2), name});
    };
    // Per level: its operator, transfers and smoother, and the cycle's vectors. Level 0's right-
    // hand side is the conjugate gradients' r and its result their z.
    struct LevelHandles {
        MatrixHandles a, prolong, restrict_;
        BufferHandle smoother, b, x, r, out;
    };
    std::vector<LevelHandles> levels;
    for (std::size_t l = 0; l < levels_.size(); ++l) {
        Level& level = levels_[l];
        const std::string name = "plane mg " + std::to_string(l);
        levels.push_back({import(level.a), import(level.prolong), import(level.restrict_), g.import_buffer(level.smoother),
                          l ? vector(level.a.rows, name + " b") : BufferHandle{}, vector(level.a.rows, name + " x"),
                          vector(level.a.rows, name + " r"), l ? vector(level.a.rows, name + " out") : BufferHandle{}});
    }
    const MatrixHandles finest = levels.empty() ? import(finest_) : levels.front().a;
    auto coarsest_inverse = g.import_buffer(coarsest_inverse_);
    auto coarsest_b = vector(coarsest_rows_, "plane mg coarsest b");
    auto coarsest_x = vector(coarsest_rows_, "plane mg coarsest x");
    auto x = g.import_buffer(x_);
    auto r = g.import_buffer(r_);
    auto p = g.import_buffer(p_);
    auto q = g.import_buffer(q_);
    auto z = vector(rows_, "plane cg z");
    BufferHandle rz[2] = {g.import_buffer(rz_[0]), g.import_buffer(rz_[1])};
    auto pq = g.import_buffer(pq_);
    auto terms = g.create_buffer({VkDeviceSize(std::max<std::uint32_t>(rows_, 1)) * sizeof(double), "plane cg terms"});
    const std::uint32_t rows = rows_, coarsest_rows = coarsest_rows_;

    // z = V-cycle(r), and r.z's terms.
    auto add_cycle = [&](const std::string& suffix) {
        const std::size_t depth = levels.size();
        for (std::size_t l = 0; l < depth; ++l) {
            LevelHandles& level = levels[l];
            const BufferHandle b = l ? level.b : r;
            BufferHandle& coarse_b = l + 1 < depth ? levels[l + 1].b : coarsest_b;
            const std::string name = "plane mg " + std::to_string(l);
            g.add_compute_pass(name + " presmooth" + suffix, [&](PassBuilder& pb) {
                for (BufferHandle h : {level.a.offsets, level.a.columns, level.a.values, level.smoother, b}) pb.read(h, Access::ComputeRead);
                level.x = pb.write(level.x, Access::ComputeWrite);
                level.r = pb.write(level.r, Access::ComputeWrite);
            }, [=, a = level.a, s = level.smoother, lx = level.x, lr = level.r](Cmd& cmd) {
                cmd.dispatch_threads(kPresmooth, {a.rows}, {a.offsets, a.columns, a.values, s, b, lx, lr}, a.rows);
            });
            g.add_compute_pass(name + " restrict" + suffix, [&](PassBuilder& pb) {
                for (BufferHandle h : {level.restrict_.offsets, level.restrict_.columns, level.restrict_.values, level.r}) pb.read(h, Access::ComputeRead);
                coarse_b = pb.write(coarse_b, Access::ComputeWrite);
            }, [=, m = level.restrict_, v = level.r, y = coarse_b](Cmd& cmd) {
                cmd.dispatch_threads(kTransfer, {m.rows}, {m.offsets, m.columns, m.values, v, y}, RowsAndSwitch{m.rows, 0});
            });
        }
        // With no smoothed level the dense solve is the whole cycle and writes r.z's terms.
        const bool alone = depth == 0;
        const BufferHandle dense_b = alone ? r : coarsest_b;
        BufferHandle& dense_x = alone ? z : coarsest_x;
        g.add_compute_pass("plane mg coarsest" + suffix, [&](PassBuilder& pb) {
            pb.read(coarsest_inverse, Access::ComputeRead);
            pb.read(dense_b, Access::ComputeRead);
            dense_x = pb.write(dense_x, Access::ComputeWrite);
            if (alone) terms = pb.write(terms, Access::ComputeWrite);
        }, [=, inv = coarsest_inverse, out = dense_x, t = terms](Cmd& cmd) {
            cmd.dispatch_threads(kCoarsest, {coarsest_rows}, {inv, dense_b, out, alone ? t : out},
                                 RowsAndSwitch{coarsest_rows, alone ? 1u : 0u});
        });
        for (std::size_t l = depth; l-- > 0;) {
            LevelHandles& level = levels[l];
            const BufferHandle b = l ? level.b : r;
            const BufferHandle coarse_x = l + 1 < depth ? levels[l + 1].out : coarsest_x;
            const std::string name = "plane mg " + std::to_string(l);
            g.add_compute_pass(name + " prolong" + suffix, [&](PassBuilder& pb) {
                for (BufferHandle h : {level.prolong.offsets, level.prolong.columns, level.prolong.values, coarse_x}) pb.read(h, Access::ComputeRead);
                level.x = pb.write(level.x, Access::ComputeReadWrite);
            }, [=, m = level.prolong, y = level.x](Cmd& cmd) {
                cmd.dispatch_threads(kTransfer, {m.rows}, {m.offsets, m.columns, m.values, coarse_x, y}, RowsAndSwitch{m.rows, 1});
            });
            BufferHandle& out = l ? level.out : z;
            g.add_compute_pass(name + " postsmooth" + suffix, [&](PassBuilder& pb) {
                for (BufferHandle h : {level.a.offsets, level.a.columns, level.a.values, level.smoother, b, level.x}) pb.read(h, Access::ComputeRead);
                out = pb.write(out, Access::ComputeWrite);
                if (l == 0) terms = pb.write(terms, Access::ComputeWrite);
            }, [=, a = level.a, s = level.smoother, lx = level.x, o = out, t = terms](Cmd& cmd) {
                const RowsAndSwitch push{a.rows, l == 0 ? 1u : 0u};
                if (l == 0) cmd.dispatch_threads(kPostsmooth, {a.rows}, {a.offsets, a.columns, a.values, s, b, lx, o, t}, push);
                else cmd.dispatch_threads(kPostsmooth, {a.rows}, {a.offsets, a.columns, a.values, s, b, lx, o, o}, push);
            });
        }
    };

    g.add_loop(iterations / 2, [&] {
        for (int half = 0; half < 2; ++half) {
            const BufferHandle rz_old = rz[half];
            const std::string suffix = half ? " (odd)" : " (even)";
            g.add_compute_pass("plane cg apply" + suffix, [&](PassBuilder& b) {
                for (BufferHandle h : {p, finest.offsets, finest.columns, finest.values}) b.read(h, Access::ComputeRead);
                q = b.write(q, Access::ComputeWrite);
                terms = b.write(terms, Access::ComputeWrite);
            }, [=](Cmd& cmd) { cmd.dispatch_threads(kApply, {rows}, {p, finest.offsets, finest.columns, finest.values, q, terms}, rows); });
            pq = add_reduce_sum_f64(g, terms, pq, rows, 1, "plane cg p.q" + suffix);
            g.add_compute_pass("plane cg step" + suffix, [&](PassBuilder& b) {
                for (BufferHandle h : {pq, rz_old, p, q}) b.read(h, Access::ComputeRead);
                x = b.write(x, Access::ComputeReadWrite);
                r = b.write(r, Access::ComputeReadWrite);
            }, [=](Cmd& cmd) { cmd.dispatch_threads(kStep, {rows}, {pq, rz_old, p, q, x, r}, rows); });
            add_cycle(suffix);
            const BufferHandle rz_new = rz[1 - half] = add_reduce_sum_f64(g, terms, rz[1 - half], rows, 1, "plane cg r.z" + suffix);
            g.add_compute_pass("plane cg direction" + suffix, [&](PassBuilder& b) {
                for (BufferHandle h : {rz_old, rz_new, z}) b.read(h, Access::ComputeRead);
                p = b.write(p, Access::ComputeReadWrite);
            }, [=](Cmd& cmd) { cmd.dispatch_threads(kDirection, {rows}, {rz_old, rz_new, z, p}, rows); });
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

PlaneSolve solve_plane_gpu(Context& ctx, const PlaneProblem& problem, const PlaneMultigrid& mg, double tolerance,
                           std::uint32_t per_check, std::size_t max_iterations, bool timestamps,
                           const std::function<void(std::size_t, double)>& progress) {
    GpuPlaneCg cg(ctx, problem, mg);
    cg.set_timestamps(timestamps);
    PlaneSolve solve;
    while (solve.iterations < max_iterations && std::isfinite(solve.residual) && solve.residual > tolerance) {
        solve.residual = cg.run(per_check);
        solve.iterations += per_check;
        solve.gpu_ms += cg.last_gpu_ms();
        if (progress) progress(solve.iterations, solve.residual);
    }
    solve.x = cg.solution();
    return solve;
}

}  // namespace gimg::passes::detail

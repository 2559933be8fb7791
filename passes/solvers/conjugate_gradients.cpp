// Multigrid-preconditioned conjugate gradients for the planar polish on the render graph, and its
// CPU twin.
#include "solvers/conjugate_gradients.h"

#include "gimg/engine/graph.h"
#include "gimg/passes/primitives.h"

#include "solvers/cg_apply_comp.h"
#include "solvers/cg_direction_comp.h"
#include "solvers/cg_step_comp.h"
#include "solvers/mg_coarsest_comp.h"
#include "solvers/mg_postsmooth_first_comp.h"
#include "solvers/mg_postsmooth_second_comp.h"
#include "solvers/mg_presmooth_first_comp.h"
#include "solvers/mg_presmooth_second_comp.h"
#include "solvers/mg_transfer_comp.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <future>

namespace gimg::passes::detail {

namespace {

const Spirv kApply = GIMG_SPIRV(gimg_spv_solvers_cg_apply_comp);
const Spirv kStep = GIMG_SPIRV(gimg_spv_solvers_cg_step_comp);
const Spirv kDirection = GIMG_SPIRV(gimg_spv_solvers_cg_direction_comp);
const Spirv kPresmoothFirst = GIMG_SPIRV(gimg_spv_solvers_mg_presmooth_first_comp);
const Spirv kPresmoothSecond = GIMG_SPIRV(gimg_spv_solvers_mg_presmooth_second_comp);
const Spirv kTransfer = GIMG_SPIRV(gimg_spv_solvers_mg_transfer_comp);
const Spirv kCoarsest = GIMG_SPIRV(gimg_spv_solvers_mg_coarsest_comp);
const Spirv kPostsmoothFirst = GIMG_SPIRV(gimg_spv_solvers_mg_postsmooth_first_comp);
const Spirv kPostsmoothSecond = GIMG_SPIRV(gimg_spv_solvers_mg_postsmooth_second_comp);

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

// Push constants of the cycle's passes: the level's rows and the pass's switch (mg_transfer:
// accumulate; mg_postsmooth_second and mg_coarsest: write r.z's terms).
struct RowsAndSwitch {
    std::uint32_t rows;
    std::uint32_t on;
};

// The smoothing passes' push constants (shaders/sphere/chebyshev.glsl), rounded to float as
// apply_multigrid_cpu rounds them.
struct SmootherPush {
    std::uint32_t rows;
    std::uint32_t write_terms;
    float theta_inverse, c0, c1, k;
};

SmootherPush smoother_push(std::uint32_t rows, bool write_terms, const ChebyshevSmoother& s) {
    return {rows, write_terms ? 1u : 0u, float(s.theta_inverse), float(s.c0), float(s.c1), float(s.k)};
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
    for (std::size_t l = 0; l < mg.levels.size(); ++l) {
        const std::string name = "plane mg level " + std::to_string(l);
        const MultigridLevel& level = mg.levels[l];
        levels_.push_back({upload_matrix_texels(ctx, level.a, level.inverse_diagonal, name + " A"),
                           upload_matrix_texels(ctx, level.prolong, {}, name + " P"),
                           upload_matrix_texels(ctx, level.restrict_, {}, name + " R"),
                           upload_float_entries(ctx, level.a, level.inverse_diagonal, name + " A D^-1 entries"),
                           level.smoother});
    }
    // q = A p in double: A's entries again, in double; its rows are level 0's when there is one.
    apply_entries_ = upload_texels(ctx, entry_texels(mg.finest()), "plane cg A entries");
    if (levels_.empty()) apply_rows_ = upload_rows(ctx, mg.finest(), {}, "plane cg A");
    coarsest_inverse_ = upload_double_texels(ctx, mg.coarsest_inverse, "plane mg coarsest inverse");
    coarsest_rows_ = std::uint32_t(mg.coarsest_rows());
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
    struct MatrixHandles {
        ImageHandle rows, entries;
        std::uint32_t count;
    };
    auto import = [&](TexelMatrix& m) {
        return MatrixHandles{g.import_image(m.rows), g.import_image(m.entries), m.row_count};
    };
    // The cycle's vectors, in float.
    auto vector = [&](std::uint32_t rows, const std::string& name) {
        return g.create_image(float_vector_desc(rows, name));
    };
    // Per level: its operator (and its entries divided by their column's diagonal), transfers,
    // and the cycle's vectors (multigrid.h names them). Level 0's right-hand side is the
    // conjugate gradients' r and its result their z.
    struct LevelHandles {
        MatrixHandles a, prolong, restrict_;
        ImageHandle ad_entries, b, mix, x, r, x1, out;
        ChebyshevSmoother smoother;
    };
    std::vector<LevelHandles> levels;
    for (std::size_t l = 0; l < levels_.size(); ++l) {
        Level& level = levels_[l];
        const std::string name = "plane mg " + std::to_string(l);
        const std::uint32_t n = level.a.row_count;
        levels.push_back({import(level.a), import(level.prolong), import(level.restrict_),
                          g.import_image(level.ad_entries), l ? vector(n, name + " b") : ImageHandle{},
                          vector(n, name + " mix"), vector(n, name + " x"), vector(n, name + " r"),
                          vector(n, name + " x1"), l ? vector(n, name + " out") : ImageHandle{}, level.smoother});
    }
    const MatrixHandles finest{levels.empty() ? g.import_image(apply_rows_) : levels.front().a.rows,
                               g.import_image(apply_entries_), rows_};
    auto coarsest_inverse = g.import_image(coarsest_inverse_);
    auto coarsest_b = vector(coarsest_rows_, "plane mg coarsest b");
    auto coarsest_x = vector(coarsest_rows_, "plane mg coarsest x");
    auto x = g.import_image(x_);
    auto r = g.import_image(r_);
    auto p = g.import_image(p_);
    auto q = g.import_image(q_);
    auto r32 = vector(rows_, "plane cg r (float)");  // the cycle's b on the finest level
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
            const ImageHandle b = l ? level.b : r32;
            ImageHandle& coarse_b = l + 1 < depth ? levels[l + 1].b : coarsest_b;
            const std::string name = "plane mg " + std::to_string(l);
            const SmootherPush push = smoother_push(level.a.count, false, level.smoother);
            g.add_compute_pass(
                name + " presmooth 1" + suffix,
                [&](PassBuilder& pb) {
                    for (ImageHandle h : {level.a.rows, level.ad_entries, b}) pb.read(h, Access::ComputeRead);
                    level.mix = pb.write(level.mix, Access::ComputeWrite);
                },
                [=, a = level.a, ad = level.ad_entries, mix = level.mix](Cmd& cmd) {
                    cmd.dispatch_threads(kPresmoothFirst, {a.count}, {a.rows, ad, b, mix}, push);
                });
            g.add_compute_pass(
                name + " presmooth 2" + suffix,
                [&](PassBuilder& pb) {
                    for (ImageHandle h : {level.a.rows, level.ad_entries, b, level.mix})
                        pb.read(h, Access::ComputeRead);
                    level.x = pb.write(level.x, Access::ComputeWrite);
                    level.r = pb.write(level.r, Access::ComputeWrite);
                },
                [=, a = level.a, ad = level.ad_entries, mix = level.mix, lx = level.x, lr = level.r](Cmd& cmd) {
                    cmd.dispatch_threads(kPresmoothSecond, {a.count}, {a.rows, ad, b, mix, lx, lr}, push);
                });
            g.add_compute_pass(
                name + " restrict" + suffix,
                [&](PassBuilder& pb) {
                    for (ImageHandle h : {level.restrict_.rows, level.restrict_.entries, level.r})
                        pb.read(h, Access::ComputeRead);
                    coarse_b = pb.write(coarse_b, Access::ComputeWrite);
                },
                [=, m = level.restrict_, v = level.r, y = coarse_b](Cmd& cmd) {
                    cmd.dispatch_threads(kTransfer, {m.count}, {m.rows, m.entries, v, y}, RowsAndSwitch{m.count, 0});
                });
        }
        // With no smoothed level the dense solve is the whole cycle and writes r.z's terms.
        const bool alone = depth == 0;
        const ImageHandle dense_b = alone ? r32 : coarsest_b;
        ImageHandle& dense_x = alone ? z : coarsest_x;
        g.add_compute_pass(
            "plane mg coarsest" + suffix,
            [&](PassBuilder& pb) {
                pb.read(coarsest_inverse, Access::ComputeRead);
                pb.read(dense_b, Access::ComputeRead);
                dense_x = pb.write(dense_x, Access::ComputeWrite);
                if (alone)
                    terms = pb.write(terms, Access::ComputeWrite);
                else
                    pb.read(terms, Access::ComputeRead);  // bound, not written
            },
            [=, inv = coarsest_inverse, out = dense_x, t = terms](Cmd& cmd) {
                cmd.dispatch_threads(kCoarsest, {coarsest_rows}, {inv, dense_b, out, t},
                                     RowsAndSwitch{coarsest_rows, alone ? 1u : 0u});
            });
        for (std::size_t l = depth; l-- > 0;) {
            LevelHandles& level = levels[l];
            const ImageHandle b = l ? level.b : r32;
            const ImageHandle coarse_x = l + 1 < depth ? levels[l + 1].out : coarsest_x;
            const std::string name = "plane mg " + std::to_string(l);
            g.add_compute_pass(
                name + " prolong" + suffix,
                [&](PassBuilder& pb) {
                    for (ImageHandle h : {level.prolong.rows, level.prolong.entries, coarse_x})
                        pb.read(h, Access::ComputeRead);
                    level.x = pb.write(level.x, Access::ComputeReadWrite);
                },
                [=, m = level.prolong, y = level.x](Cmd& cmd) {
                    cmd.dispatch_threads(kTransfer, {m.count}, {m.rows, m.entries, coarse_x, y},
                                         RowsAndSwitch{m.count, 1});
                });
            g.add_compute_pass(
                name + " postsmooth 1" + suffix,
                [&](PassBuilder& pb) {
                    for (ImageHandle h : {level.a.rows, level.a.entries, b, level.x}) pb.read(h, Access::ComputeRead);
                    level.x1 = pb.write(level.x1, Access::ComputeWrite);
                },
                [=, a = level.a, lx = level.x, x1 = level.x1,
                 push = smoother_push(level.a.count, false, level.smoother)](Cmd& cmd) {
                    cmd.dispatch_threads(kPostsmoothFirst, {a.count}, {a.rows, a.entries, b, lx, x1}, push);
                });
            ImageHandle& out = l ? level.out : z;
            // Only the finest level writes r.z's terms; the others bind them unwritten.
            g.add_compute_pass(
                name + " postsmooth 2" + suffix,
                [&](PassBuilder& pb) {
                    for (ImageHandle h : {level.a.rows, level.a.entries, b, level.x, level.x1})
                        pb.read(h, Access::ComputeRead);
                    out = pb.write(out, Access::ComputeWrite);
                    if (l == 0)
                        terms = pb.write(terms, Access::ComputeWrite);
                    else
                        pb.read(terms, Access::ComputeRead);
                },
                [=, a = level.a, lx = level.x, x1 = level.x1, o = out, t = terms,
                 push = smoother_push(level.a.count, l == 0, level.smoother)](Cmd& cmd) {
                    cmd.dispatch_threads(kPostsmoothSecond, {a.count}, {a.rows, a.entries, b, lx, x1, o, t}, push);
                });
        }
    };

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
        add_cycle(suffix);
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

// Preconditioned BiCGSTAB on the render graph, and its CPU twin (bicgstab.h).
#include "solvers/bicgstab.h"

#include "solvers/matrix_texels.h"

#include "gimg/engine/graph.h"

#include "solvers/bicgstab_apply_comp.h"
#include "solvers/bicgstab_direction_comp.h"
#include "solvers/bicgstab_finish_comp.h"
#include "solvers/bicgstab_half_comp.h"
#include "solvers/bicgstab_update_comp.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace gimg::passes::detail {

namespace {

const Spirv kFinish = GIMG_SPIRV(gimg_spv_solvers_bicgstab_finish_comp);
const Spirv kDirection = GIMG_SPIRV(gimg_spv_solvers_bicgstab_direction_comp);
const Spirv kApply = GIMG_SPIRV(gimg_spv_solvers_bicgstab_apply_comp);
const Spirv kHalf = GIMG_SPIRV(gimg_spv_solvers_bicgstab_half_comp);
const Spirv kUpdate = GIMG_SPIRV(gimg_spv_solvers_bicgstab_update_comp);

// The local size of the passes that write workgroup sums (workgroup_sums.glsl's kSumThreads).
constexpr std::uint32_t kSumThreads = 64;

// The shaders' BicgScalars (bicgstab_scalars.glsl).
struct Scalars {
    glm::dvec2 rho, alpha, omega, beta;
};

struct RowsAndMode {
    std::uint32_t rows, mode;
};

struct ApplyPush {
    std::uint32_t rows, mode, float_input;
};

struct UpdatePush {
    std::uint32_t rows, float_input;
};

struct FinishPush {
    std::uint32_t groups, step;
};

glm::dvec2 times(const CsrMatrix& a, const std::vector<glm::dvec2>& v, std::size_t i) {
    glm::dvec2 sum(0.0);
    for (std::uint32_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) sum += a.values[k] * v[a.columns[k]];
    return sum;
}

std::vector<double> inverse_diagonal(const CsrMatrix& a) {
    std::vector<double> inv(a.rows(), 0.0);
    for (std::size_t i = 0; i < a.rows(); ++i)
        for (std::uint32_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k)
            if (a.columns[k] == i) inv[i] = 1.0 / a.values[k];
    return inv;
}

// beta = (rho' / rho)(alpha / omega) per right-hand side, rho' = r0 . r now (0 where rho or omega
// vanished); bicgstab_finish's step 0 on the GPU.
glm::dvec2 next_beta(const BicgState& s) {
    glm::dvec2 beta;
    for (int c = 0; c < 2; ++c)
        beta[c] = s.rho[c] != 0.0 && s.omega[c] != 0.0 ? (s.r0r[c] / s.rho[c]) * (s.alpha[c] / s.omega[c]) : 0.0;
    return beta;
}

glm::dvec2 divide_or_zero(glm::dvec2 num, glm::dvec2 den) {
    return {den.x != 0.0 ? num.x / den.x : 0.0, den.y != 0.0 ? num.y / den.y : 0.0};
}

// y = M p: D^-1 p, or the V-cycle of p (which rounds p to float, as the GPU's direction pass does).
void precondition(const std::vector<double>& inverse_diagonal, const Multigrid* mg, const std::vector<glm::dvec2>& p,
                  std::vector<glm::dvec2>& y) {
    if (mg) {
        y = apply_multigrid_cpu(*mg, p, CyclePrecision::float32);
        return;
    }
    for (std::size_t i = 0; i < p.size(); ++i) y[i] = inverse_diagonal[i] * p[i];
}

}  // namespace

SpdSystem symmetric_laplacian(const CsrMatrix& a, const std::vector<double>& boundary) {
    const std::size_t n = a.rows();
    // Row i's entries with a_ji added where (j, i) exists: transpose once, then merge by column.
    std::vector<std::vector<std::pair<std::uint32_t, double>>> rows(n);
    for (std::uint32_t i = 0; i < n; ++i)
        for (std::uint32_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) {
            const std::uint32_t j = a.columns[k];
            if (j == i) continue;
            rows[i].emplace_back(j, 0.5 * a.values[k]);
            rows[j].emplace_back(i, 0.5 * a.values[k]);
        }
    SpdSystem out;
    out.row_offsets.push_back(0);
    out.diagonal.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        std::sort(rows[i].begin(), rows[i].end(), [](const auto& l, const auto& r) { return l.first < r.first; });
        double magnitude = boundary.empty() ? 0.0 : boundary[i];
        for (std::size_t k = 0; k < rows[i].size();) {
            const std::uint32_t j = rows[i][k].first;
            double value = 0.0;
            for (; k < rows[i].size() && rows[i][k].first == j; ++k) value += rows[i][k].second;
            if (value == 0.0) continue;
            out.columns.push_back(j);
            out.values.push_back(value);
            magnitude += std::abs(value);
        }
        // Plus what A's own row has beyond diagonal dominance (a shift, a mass term), so that a
        // system without fixed rows keeps a nonsingular Laplacian: 0 on Tutte and Floater rows.
        double own = 0.0, others = boundary.empty() ? 0.0 : boundary[i];
        for (std::uint32_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k)
            (a.columns[k] == i ? own : others) += std::abs(a.values[k]);
        out.diagonal[i] = magnitude + std::max(0.0, own - others);
        out.row_offsets.push_back(std::uint32_t(out.columns.size()));
    }
    out.rhs.assign(n, glm::dvec2(0.0));
    out.start.assign(n, glm::dvec2(0.0));
    return out;
}

BicgState start_bicgstab(const CsrMatrix& a, const std::vector<glm::dvec2>& b, const std::vector<glm::dvec2>& x0) {
    BicgState s;
    const std::size_t n = a.rows();
    s.x = x0;
    s.r.resize(n);
    for (std::size_t i = 0; i < n; ++i) s.r[i] = b[i] - times(a, x0, i);
    s.r0 = s.r;
    s.p.assign(n, glm::dvec2(0.0));
    s.v.assign(n, glm::dvec2(0.0));
    for (std::size_t i = 0; i < n; ++i) {
        s.r0r += s.r0[i] * s.r[i];
        s.rr += s.r[i] * s.r[i];
    }
    return s;
}

void bicgstab_cpu(const CsrMatrix& a, BicgState& s, std::uint32_t iterations, const Multigrid* mg) {
    const std::size_t n = a.rows();
    const std::vector<double> inv = mg ? std::vector<double>() : inverse_diagonal(a);
    std::vector<glm::dvec2> y(n), sv(n), z(n), t(n);
    for (std::uint32_t it = 0; it < iterations; ++it) {
        const glm::dvec2 beta = next_beta(s);
        s.rho = s.r0r;
        for (std::size_t i = 0; i < n; ++i) s.p[i] = s.r[i] + beta * (s.p[i] - s.omega * s.v[i]);
        precondition(inv, mg, s.p, y);
        glm::dvec2 r0v(0.0);
        for (std::size_t i = 0; i < n; ++i) {
            s.v[i] = times(a, y, i);
            r0v += s.r0[i] * s.v[i];
        }
        s.alpha = divide_or_zero(s.rho, r0v);
        for (std::size_t i = 0; i < n; ++i) sv[i] = s.r[i] - s.alpha * s.v[i];
        precondition(inv, mg, sv, z);
        glm::dvec2 ts(0.0), tt(0.0);
        for (std::size_t i = 0; i < n; ++i) {
            t[i] = times(a, z, i);
            ts += sv[i] * t[i];
            tt += t[i] * t[i];
        }
        s.omega = {tt.x > 0.0 ? ts.x / tt.x : 0.0, tt.y > 0.0 ? ts.y / tt.y : 0.0};
        s.r0r = glm::dvec2(0.0);
        s.rr = glm::dvec2(0.0);
        for (std::size_t i = 0; i < n; ++i) {
            s.x[i] = s.x[i] + s.alpha * y[i] + s.omega * z[i];
            s.r[i] = sv[i] - s.omega * t[i];
            s.r0r += s.r0[i] * s.r[i];
            s.rr += s.r[i] * s.r[i];
        }
    }
}

GpuBicgstab::GpuBicgstab(Context& ctx, const CsrMatrix& a, const BicgState& start, const Multigrid* mg)
    : ctx_(ctx), rows_(std::uint32_t(a.rows())) {
    ctx.batch_uploads([&] {
        if (mg) {
            own_cycle_ = std::make_unique<GpuVcycle>(ctx, *mg, "bicgstab mg");
            cycle_ = own_cycle_.get();
        }
        upload(a, start);
    });
}

GpuBicgstab::GpuBicgstab(Context& ctx, const CsrMatrix& a, const BicgState& start, GpuVcycle& cycle)
    : ctx_(ctx), rows_(std::uint32_t(a.rows())), cycle_(&cycle) {
    ctx.batch_uploads([&] { upload(a, start); });
}

void GpuBicgstab::upload(const CsrMatrix& a, const BicgState& start) {
    Context& ctx = ctx_;
    check_texel_array_size(ctx, a.values.size(), "BiCGSTAB matrix entries");
    a_rows_ = upload_rows(ctx, a, inverse_diagonal(a), "bicgstab A");
    a_entries_ = upload_texels(ctx, entry_texels(a), "bicgstab A entries");
    x_ = upload_vector_texels(ctx, start.x, "bicgstab x");
    r_ = upload_vector_texels(ctx, start.r, "bicgstab r");
    r0_ = upload_vector_texels(ctx, start.r0, "bicgstab r0");
    p_ = upload_vector_texels(ctx, start.p, "bicgstab p");
    v_ = upload_vector_texels(ctx, start.v, "bicgstab v");
    y_ = ctx.create_image(texel_image_desc(rows_, "bicgstab y"));
    s_ = ctx.create_image(texel_image_desc(rows_, "bicgstab s"));
    z_ = ctx.create_image(texel_image_desc(rows_, "bicgstab z"));
    t_ = ctx.create_image(texel_image_desc(rows_, "bicgstab t"));
    // Each iteration's beta comes from the last one's finishing pass; the first one's from here.
    const Scalars scalars{start.r0r, start.alpha, start.omega, next_beta(start)};
    scalars_ = ctx.create_buffer({sizeof(Scalars), "bicgstab scalars"});
    ctx.upload(scalars_, &scalars, sizeof scalars);
    sums_rr_ = ctx.create_buffer({4 * sizeof(double), "bicgstab r0.r r.r"}, MemoryUsage::Readback);
    const double rr[4] = {start.r0r.x, start.r0r.y, start.rr.x, start.rr.y};
    ctx.upload(sums_rr_, rr, sizeof rr);
}

Plan& GpuBicgstab::plan_for(std::uint32_t iterations) {
    auto& slot = plans_[iterations];
    if (slot) return *slot;
    Graph g(ctx_);
    auto rows_img = g.import_image(a_rows_);
    auto entries = g.import_image(a_entries_);
    auto x = g.import_image(x_), r = g.import_image(r_), r0 = g.import_image(r0_), p = g.import_image(p_);
    auto v = g.import_image(v_), y = g.import_image(y_), s = g.import_image(s_), z = g.import_image(z_);
    auto t = g.import_image(t_);
    auto scalars = g.import_buffer(scalars_);
    auto rr = g.import_buffer(sums_rr_);
    const std::uint32_t n = rows_;
    const std::uint32_t groups = (n + kSumThreads - 1) / kSumThreads;
    auto partials = g.create_buffer({VkDeviceSize(groups) * 4 * sizeof(double), "bicgstab workgroup sums"});
    // With the multigrid cycle: p and s rounded to float, the cycle's float outputs y32 and z32,
    // which the products and the update read as they are (widening is exact), and the cycle itself.
    const std::uint32_t multigrid = cycle_ ? 1u : 0u;
    const std::uint32_t float_rows = cycle_ ? n : 1u;
    auto p32 = g.create_image(float_vector_desc(float_rows, "bicgstab p (float)"));
    auto s32 = g.create_image(float_vector_desc(float_rows, "bicgstab s (float)"));
    auto y32 = g.create_image(float_vector_desc(float_rows, "bicgstab y (float)"));
    auto z32 = g.create_image(float_vector_desc(float_rows, "bicgstab z (float)"));
    std::optional<VcycleRecorder> cycle;
    if (cycle_) cycle.emplace(g, *cycle_);
    // The sums of the pass before, finished, and the scalars of `step` (bicgstab_finish.comp).
    auto add_finish = [&](std::uint32_t step, const std::string& name) {
        g.add_compute_pass(
            name,
            [&](PassBuilder& b) {
                b.read(partials, Access::ComputeRead);
                scalars = b.write(scalars, Access::ComputeReadWrite);
                rr = b.write(rr, Access::ComputeWrite);
            },
            [=, sc = scalars, out = rr](Cmd& c) {
                c.dispatch(kFinish, {1}, {sc, partials, out}, FinishPush{groups, step});
            });
    };
    auto add_product = [&](ImageHandle in, ImageHandle in_32, ImageHandle w, ImageHandle& out, std::uint32_t mode,
                           const std::string& name) {
        g.add_compute_pass(
            name,
            [&](PassBuilder& b) {
                for (ImageHandle h : {rows_img, entries, in, in_32, w}) b.read(h, Access::ComputeRead);
                out = b.write(out, Access::ComputeWrite);
                partials = b.write(partials, Access::ComputeWrite);
            },
            [=, o = out, sums = partials](Cmd& c) {
                c.dispatch_threads(kApply, {n}, {rows_img, entries, in, in_32, w, o, sums},
                                   ApplyPush{n, mode, multigrid});
            });
    };
    g.add_loop(iterations, [&] {
        g.add_compute_pass(
            "bicgstab direction",
            [&](PassBuilder& b) {
                for (ImageHandle h : {rows_img, r, v}) b.read(h, Access::ComputeRead);
                b.read(scalars, Access::ComputeRead);
                p = b.write(p, Access::ComputeReadWrite);
                y = b.write(y, Access::ComputeWrite);
                p32 = b.write(p32, Access::ComputeWrite);
            },
            [=](Cmd& c) {
                c.dispatch_threads(kDirection, {n}, {scalars, rows_img, r, v, p, y, p32}, RowsAndMode{n, multigrid});
            });
        if (cycle) cycle->add(p32, y32, partials, false, " (y)");
        add_product(y, y32, r0, v, 0, "bicgstab v = A y");
        add_finish(1, "bicgstab alpha");
        g.add_compute_pass(
            "bicgstab s",
            [&](PassBuilder& b) {
                for (ImageHandle h : {rows_img, r, v}) b.read(h, Access::ComputeRead);
                b.read(scalars, Access::ComputeRead);
                s = b.write(s, Access::ComputeWrite);
                z = b.write(z, Access::ComputeWrite);
                s32 = b.write(s32, Access::ComputeWrite);
            },
            [=](Cmd& c) {
                c.dispatch_threads(kHalf, {n}, {scalars, rows_img, r, v, s, z, s32}, RowsAndMode{n, multigrid});
            });
        if (cycle) cycle->add(s32, z32, partials, false, " (z)");
        add_product(z, z32, s, t, 1, "bicgstab t = A z");
        add_finish(2, "bicgstab omega");
        g.add_compute_pass(
            "bicgstab update",
            [&](PassBuilder& b) {
                for (ImageHandle h : {y, z, y32, z32, s, t, r0}) b.read(h, Access::ComputeRead);
                b.read(scalars, Access::ComputeRead);
                x = b.write(x, Access::ComputeReadWrite);
                r = b.write(r, Access::ComputeWrite);
                partials = b.write(partials, Access::ComputeWrite);
            },
            [=, sums = partials](Cmd& c) {
                c.dispatch_threads(kUpdate, {n}, {scalars, y, z, y32, z32, s, t, r0, x, r, sums},
                                   UpdatePush{n, multigrid});
            });
        add_finish(0, "bicgstab beta");
    });
    g.export_buffer(rr, Access::HostRead);
    g.export_buffer(scalars, Access::ComputeReadWrite);
    for (ImageHandle h : {x, r, p, v}) g.export_image(h, Access::ComputeReadWrite);
    slot = std::make_unique<Plan>(g.compile());
    return *slot;
}

std::pair<glm::dvec2, glm::dvec2> GpuBicgstab::run(std::uint32_t iterations) {
    if (rows_ > 0 && iterations > 0) plan_for(iterations).execute({.wait = true});
    const std::vector<double> sums = ctx_.download<double>(sums_rr_);
    return {{sums[0], sums[1]}, {sums[2], sums[3]}};
}

std::vector<glm::dvec2> GpuBicgstab::solution() {
    if (rows_ == 0) return {};
    return download_vector_texels(ctx_, x_, rows_);
}

}  // namespace gimg::passes::detail

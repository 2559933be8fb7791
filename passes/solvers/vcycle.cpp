// The multigrid V-cycle's passes on the render graph (vcycle.h).
#include "solvers/vcycle.h"

#include "solvers/mg_coarsest_comp.h"
#include "solvers/mg_postsmooth_first_comp.h"
#include "solvers/mg_postsmooth_second_comp.h"
#include "solvers/mg_presmooth_first_comp.h"
#include "solvers/mg_presmooth_second_comp.h"
#include "solvers/mg_transfer_comp.h"

namespace gimg::passes::detail {

namespace {

const Spirv kPresmoothFirst = GIMG_SPIRV(gimg_spv_solvers_mg_presmooth_first_comp);
const Spirv kPresmoothSecond = GIMG_SPIRV(gimg_spv_solvers_mg_presmooth_second_comp);
const Spirv kTransfer = GIMG_SPIRV(gimg_spv_solvers_mg_transfer_comp);
const Spirv kCoarsest = GIMG_SPIRV(gimg_spv_solvers_mg_coarsest_comp);
const Spirv kPostsmoothFirst = GIMG_SPIRV(gimg_spv_solvers_mg_postsmooth_first_comp);
const Spirv kPostsmoothSecond = GIMG_SPIRV(gimg_spv_solvers_mg_postsmooth_second_comp);

// Push constants of the cycle's passes: the level's rows and the pass's switch (mg_transfer:
// accumulate; mg_coarsest: write b.z's terms).
struct RowsAndSwitch {
    std::uint32_t rows;
    std::uint32_t on;
};

// The smoothing passes' push constants (shaders/solvers/chebyshev.glsl), rounded to float as
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

GpuVcycle::GpuVcycle(Context& ctx, const Multigrid& mg, const std::string& name) : name_(name) {
    for (std::size_t l = 0; l < mg.levels.size(); ++l) {
        const std::string level_name = name + " level " + std::to_string(l);
        const MultigridLevel& level = mg.levels[l];
        levels_.push_back({upload_matrix_texels(ctx, level.a, level.a32, level.inverse_diagonal, level_name + " A"),
                           upload_matrix_texels(ctx, level.prolong, level.prolong32, {}, level_name + " P"),
                           upload_matrix_texels(ctx, level.restrict_, level.restrict32, {}, level_name + " R"),
                           upload_float_entries(ctx, level.a, level.a_over_diagonal32, level_name + " A D^-1 entries"),
                           level.smoother});
    }
    coarsest_inverse_ = upload_double_texels(ctx, mg.coarsest_inverse, name + " coarsest inverse");
    coarsest_rows_ = std::uint32_t(mg.coarsest_rows());
}

VcycleRecorder::VcycleRecorder(Graph& g, GpuVcycle& cycle) : g_(g), name_(cycle.name_) {
    auto import = [&](TexelMatrix& m) {
        return MatrixHandles{g.import_image(m.rows), g.import_image(m.entries), m.row_count};
    };
    auto vector = [&](std::uint32_t rows, const std::string& name) {
        return g.create_image(float_vector_desc(rows, name));
    };
    // Level 0's right-hand side and result are the caller's b and z.
    for (std::size_t l = 0; l < cycle.levels_.size(); ++l) {
        GpuVcycle::Level& level = cycle.levels_[l];
        const std::string name = name_ + " " + std::to_string(l);
        const std::uint32_t n = level.a.row_count;
        levels_.push_back({import(level.a), import(level.prolong), import(level.restrict_),
                           g.import_image(level.ad_entries), l ? vector(n, name + " b") : ImageHandle{},
                           vector(n, name + " mix"), vector(n, name + " x"), vector(n, name + " r"),
                           vector(n, name + " x1"), l ? vector(n, name + " out") : ImageHandle{}, level.smoother});
    }
    coarsest_rows_ = cycle.coarsest_rows_;
    coarsest_inverse_ = g.import_image(cycle.coarsest_inverse_);
    coarsest_b_ = vector(coarsest_rows_, name_ + " coarsest b");
    coarsest_x_ = vector(coarsest_rows_, name_ + " coarsest x");
}

void VcycleRecorder::add(ImageHandle b0, ImageHandle& z, BufferHandle& terms, bool write_terms,
                         const std::string& suffix) {
    Graph& g = g_;
    const std::size_t depth = levels_.size();
    for (std::size_t l = 0; l < depth; ++l) {
        LevelHandles& level = levels_[l];
        const ImageHandle b = l ? level.b : b0;
        ImageHandle& coarse_b = l + 1 < depth ? levels_[l + 1].b : coarsest_b_;
        const std::string name = name_ + " " + std::to_string(l);
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
                for (ImageHandle h : {level.a.rows, level.ad_entries, b, level.mix}) pb.read(h, Access::ComputeRead);
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
    // With no smoothed level the dense solve is the whole cycle, and writes the terms.
    const bool alone = depth == 0;
    const ImageHandle dense_b = alone ? b0 : coarsest_b_;
    ImageHandle& dense_x = alone ? z : coarsest_x_;
    const bool dense_terms = alone && write_terms;
    const std::uint32_t coarsest_rows = coarsest_rows_;
    g.add_compute_pass(
        name_ + " coarsest" + suffix,
        [&](PassBuilder& pb) {
            pb.read(coarsest_inverse_, Access::ComputeRead);
            pb.read(dense_b, Access::ComputeRead);
            dense_x = pb.write(dense_x, Access::ComputeWrite);
            if (dense_terms)
                terms = pb.write(terms, Access::ComputeWrite);
            else
                pb.read(terms, Access::ComputeRead);  // bound, not written
        },
        [=, inv = coarsest_inverse_, out = dense_x, t = terms](Cmd& cmd) {
            cmd.dispatch_threads(kCoarsest, {coarsest_rows}, {inv, dense_b, out, t},
                                 RowsAndSwitch{coarsest_rows, dense_terms ? 1u : 0u});
        });
    for (std::size_t l = depth; l-- > 0;) {
        LevelHandles& level = levels_[l];
        const ImageHandle b = l ? level.b : b0;
        const ImageHandle coarse_x = l + 1 < depth ? levels_[l + 1].out : coarsest_x_;
        const std::string name = name_ + " " + std::to_string(l);
        g.add_compute_pass(
            name + " prolong" + suffix,
            [&](PassBuilder& pb) {
                for (ImageHandle h : {level.prolong.rows, level.prolong.entries, coarse_x})
                    pb.read(h, Access::ComputeRead);
                level.x = pb.write(level.x, Access::ComputeReadWrite);
            },
            [=, m = level.prolong, y = level.x](Cmd& cmd) {
                cmd.dispatch_threads(kTransfer, {m.count}, {m.rows, m.entries, coarse_x, y}, RowsAndSwitch{m.count, 1});
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
        // Only the finest level may write the terms; the others bind them unwritten.
        const bool level_terms = l == 0 && write_terms;
        g.add_compute_pass(
            name + " postsmooth 2" + suffix,
            [&](PassBuilder& pb) {
                for (ImageHandle h : {level.a.rows, level.a.entries, b, level.x, level.x1})
                    pb.read(h, Access::ComputeRead);
                out = pb.write(out, Access::ComputeWrite);
                if (level_terms)
                    terms = pb.write(terms, Access::ComputeWrite);
                else
                    pb.read(terms, Access::ComputeRead);
            },
            [=, a = level.a, lx = level.x, x1 = level.x1, o = out, t = terms,
             push = smoother_push(level.a.count, level_terms, level.smoother)](Cmd& cmd) {
                cmd.dispatch_threads(kPostsmoothSecond, {a.count}, {a.rows, a.entries, b, lx, x1, o, t}, push);
            });
    }
}

}  // namespace gimg::passes::detail

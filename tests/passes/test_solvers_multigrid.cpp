// The multigrid preconditioner of the solvers module, on the sphere map's chart problems: its hierarchy coarsens, its
// V-cycle is the symmetric positive definite operator conjugate gradients need, it solves small
// problems exactly, with it the iterations stay flat as the mesh grows, and the GPU's cycle is its
// CPU twin's to the bit.
#include "gpu_test.h"
#include "solvers/conjugate_gradients.h"
#include "solvers/multigrid.h"
#include "solvers/vcycle.h"
#include "sphere/harmonic/chart_problem.h"
#include "sphere/harmonic/relaxation_mesh.h"

#include "gimg/engine/error.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

using namespace gimg;
using namespace gimg::passes::detail;

namespace {

// An icosphere pushed into a lumpy ellipsoid (cotangent weights far from uniform), and its
// planar problem with the undeformed sphere as the "relaxed map" (flip-free by construction).
struct Case {
    geo::Mesh mesh;
    ChartProblem problem;
};

Case lumpy_case(int subdivisions) {
    Case c;
    c.mesh = geo::make_icosphere(1.0, subdivisions);
    std::vector<glm::dvec3> sphere(c.mesh.positions.size());
    for (std::size_t i = 0; i < sphere.size(); ++i) sphere[i] = glm::normalize(c.mesh.positions[i]);
    for (auto& p : c.mesh.positions) p = glm::dvec3(p.x, 2.0 * p.y, p.z) * (1.0 + 0.2 * p.x * p.y);
    c.problem = make_chart_problem(build_relaxation_mesh(c.mesh), sphere);
    return c;
}

std::vector<glm::dvec2> pseudo_random(std::size_t n, double seed) {
    std::vector<glm::dvec2> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = {std::sin(seed * double(i + 1)), std::cos(1.7 * seed * double(i + 3))};
    return v;
}

double dot(const std::vector<glm::dvec2>& a, const std::vector<glm::dvec2>& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) s += glm::dot(a[i], b[i]);
    return s;
}

// Conjugate gradients from zero until the relative residual is below `tolerance`.
std::uint32_t iterations_to(const ChartProblem& problem, const Multigrid& mg, double tolerance) {
    ChartProblem from_zero = problem;
    from_zero.start.assign(problem.rows(), glm::dvec2(0.0));
    CgState state = start_cg(from_zero, mg);
    std::uint32_t iterations = 0;
    while (state.relative_residual() > tolerance && iterations < 1000) {
        cg_cpu(mg, state, 1);
        ++iterations;
    }
    return iterations;
}

// z = V-cycle(b) on the GPU: one graph with the cycle's passes, b and z as float texel arrays.
std::vector<glm::vec2> gpu_cycle(Context& ctx, GpuVcycle& cycle, const std::vector<glm::dvec2>& b) {
    std::vector<glm::vec2> b32(b.begin(), b.end());
    Image b_image = upload_texel_array(ctx, b32, Format::RG32F, "cycle b");
    Image z_image = ctx.create_image(float_vector_desc(b.size(), "cycle z"));
    Buffer terms = ctx.create_buffer({b.size() * sizeof(double), "cycle terms"});
    Graph g(ctx);
    ImageHandle z = g.import_image(z_image);
    BufferHandle t = g.import_buffer(terms);
    VcycleRecorder recorder(g, cycle);
    recorder.add(g.import_image(b_image), z, t, false, "");
    g.export_image(z, Access::TransferSrc);
    g.compile().execute({.wait = true});
    const std::vector<std::byte> bytes = ctx.download(z_image);
    std::vector<glm::vec2> out(b.size());
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(glm::vec2));
    return out;
}

class SolversMultigridGpu : public test::GpuTest {};

}  // namespace

TEST(SolversMultigrid, CoarsensToADenseLevelWithTransposedTransfers) {
    const Case c = lumpy_case(5);  // 10,242 vertices
    const Multigrid mg = build_multigrid(c.problem);
    ASSERT_GE(mg.levels.size(), 2u);
    EXPECT_EQ(mg.rows(), c.problem.rows());
    EXPECT_LE(mg.coarsest_rows(), kMultigridDenseRows);
    EXPECT_EQ(mg.coarsest_inverse.size(), mg.coarsest_rows() * mg.coarsest_rows());
    for (std::size_t l = 0; l < mg.levels.size(); ++l) {
        const MultigridLevel& level = mg.levels[l];
        const std::size_t coarse = l + 1 < mg.levels.size() ? mg.levels[l + 1].a.rows() : mg.coarsest_rows();
        EXPECT_LE(3 * coarse, level.a.rows()) << "level " << l;  // at least 3x fewer rows a level
        ASSERT_EQ(level.prolong.rows(), level.a.rows());
        ASSERT_EQ(level.prolong.cols, coarse);
        ASSERT_EQ(level.restrict_.rows(), coarse);
        ASSERT_EQ(level.inverse_diagonal.size(), level.a.rows());
        // R = P^T entry by entry.
        std::size_t checked = 0;
        for (std::uint32_t i = 0; i < level.prolong.rows(); ++i)
            for (std::uint32_t k = level.prolong.offsets[i]; k < level.prolong.offsets[i + 1]; ++k) {
                const std::uint32_t j = level.prolong.columns[k];
                double r = 0.0;
                for (std::uint32_t m = level.restrict_.offsets[j]; m < level.restrict_.offsets[j + 1]; ++m)
                    if (level.restrict_.columns[m] == i) r = level.restrict_.values[m];
                EXPECT_EQ(r, level.prolong.values[k]);
                ++checked;
            }
        EXPECT_EQ(checked, level.restrict_.values.size());
    }
}

TEST(SolversMultigrid, ChebyshevSmootherIsTheDegreeTwoMinimaxPolynomial) {
    // On a 1x1 "matrix" a with diagonal a (D^-1 A = 1) scaled so that D^-1 A's eigenvalue is
    // lambda: the smoother's error factor 1 - lambda q(lambda) from zero and from any x is the same
    // polynomial, at most 1 / T2(theta / delta) on [rho / 10, 1.2 rho] (equal at both ends and in
    // the middle: the minimax property), and below 1 up to 1.3 rho.
    const double rho = 1.7;
    const ChebyshevSmoother s = chebyshev_smoother(rho);
    const double low = 0.1 * rho, high = 1.2 * rho, theta = 0.5 * (high + low), delta = 0.5 * (high - low);
    const double sigma = theta / delta, bound = 1.0 / (2.0 * sigma * sigma - 1.0);
    auto from_zero = [&](double lambda) {  // x = c0 b + c1 (b - lambda b / theta), b = 1
        return 1.0 - lambda * (s.c0 + s.c1 * (1.0 - lambda * s.theta_inverse));
    };
    auto from_x = [&](double lambda, double x0) {  // error (x* - x) / (x* - x0), x* = 1 / lambda
        const double d = s.theta_inverse * (1.0 - lambda * x0), x1 = x0 + d;
        const double x2 = x1 + s.k * d + s.c1 * (1.0 - lambda * x1);
        return (1.0 / lambda - x2) / (1.0 / lambda - x0);
    };
    double worst = 0.0;
    for (int i = 0; i <= 100; ++i) {
        const double lambda = low + (high - low) * i / 100.0;
        worst = std::max(worst, std::abs(from_zero(lambda)));
        EXPECT_NEAR(from_x(lambda, 0.3), from_zero(lambda), 1e-12) << lambda;
    }
    EXPECT_NEAR(worst, bound, 1e-12);
    for (double lambda : {low, theta, high}) EXPECT_NEAR(std::abs(from_zero(lambda)), bound, 1e-12) << lambda;
    for (int i = 1; i < 130; ++i) EXPECT_LT(std::abs(from_zero(rho * i / 100.0)), 1.0) << i;
    EXPECT_GT(std::abs(from_zero(1.32 * rho)), 1.0);  // past the margin it amplifies
}

TEST(SolversMultigrid, VCycleIsSymmetricAndPositiveDefinite) {
    // Conjugate gradients need M = M^T > 0: the same Chebyshev smoother before and after on every
    // level. In double, to double's rounding; the GPU's float cycle to float's (its rounding
    // differs between u and v: 4e-9 of the scale measured).
    const Case c = lumpy_case(4);
    const Multigrid mg = build_multigrid(c.problem);
    ASSERT_GE(mg.levels.size(), 1u);
    for (const auto& [precision, tolerance] :
         {std::pair{CyclePrecision::float64, 1e-12}, std::pair{CyclePrecision::float32, 1e-6}}) {
        for (double seed : {0.3, 1.1, 2.9}) {
            const auto u = pseudo_random(mg.rows(), seed), v = pseudo_random(mg.rows(), seed + 0.7);
            const auto mu = apply_multigrid_cpu(mg, u, precision), mv = apply_multigrid_cpu(mg, v, precision);
            const double scale = std::sqrt(dot(u, u) * dot(mv, mv));
            EXPECT_NEAR(dot(u, mv), dot(v, mu), tolerance * scale) << seed;
            EXPECT_GT(dot(u, mu), 0.0) << seed;
        }
    }
}

TEST(SolversMultigrid, FloatCycleIsTheDoubleCycleToFloatRounding) {
    // The GPU's cycle in float (and its CPU twin) computes the double cycle's z to a few units of
    // float's rounding, relative to z's largest element, on a hierarchy of several levels.
    const Case c = lumpy_case(5);
    const Multigrid mg = build_multigrid(c.problem);
    ASSERT_GE(mg.levels.size(), 2u);
    for (double seed : {0.3, 1.1}) {
        const auto b = pseudo_random(mg.rows(), seed);
        const auto z32 = apply_multigrid_cpu(mg, b, CyclePrecision::float32);
        const auto z64 = apply_multigrid_cpu(mg, b, CyclePrecision::float64);
        double worst = 0.0, largest = 0.0;
        for (std::size_t i = 0; i < b.size(); ++i) {
            worst = std::max(worst, glm::length(z32[i] - z64[i]));
            largest = std::max(largest, glm::length(z64[i]));
        }
        std::printf("seed %.1f: |z32 - z64| <= %.2e of |z|\n", seed, worst / largest);
        EXPECT_LT(worst, 1e-5 * largest) << seed;
        EXPECT_GT(worst, 0.0) << seed;  // it does run in float
    }
}

TEST(SolversMultigrid, SolvesASmallProblemExactly) {
    // 162 vertices: no smoothed level, the cycle is the dense inverse, A (M b) = b: in double to
    // double's rounding; in the GPU's float cycle, whose b and x are rounded to float, to float's
    // (5e-7 measured), and conjugate gradients still need only 2 iterations.
    const Case c = lumpy_case(2);
    const Multigrid mg = build_multigrid(c.problem);
    ASSERT_TRUE(mg.levels.empty());
    const auto b = pseudo_random(mg.rows(), 0.5);
    for (const auto& [precision, tolerance] :
         {std::pair{CyclePrecision::float64, 1e-10}, std::pair{CyclePrecision::float32, 1e-5}}) {
        const auto x = apply_multigrid_cpu(mg, b, precision);
        double worst = 0.0, largest = 0.0;
        for (std::size_t i = 0; i < b.size(); ++i) {
            worst = std::max(worst, glm::length(row_times(mg.finest(), x, i) - b[i]));
            largest = std::max(largest, glm::length(b[i]));
        }
        EXPECT_LT(worst, tolerance * largest);
    }
    EXPECT_LE(iterations_to(c.problem, mg, 1e-10), 2u);
}

TEST(SolversMultigrid, IterationsStayFlatAsTheMeshGrows) {
    // Jacobi-preconditioned conjugate gradients need about as many iterations as the mesh has
    // rings across (in the polish: 900 on bunny, 1,856 on armadillo_loop1); with the V-cycle the
    // count must stay flat over a 16x finer mesh. (With one damped Jacobi step each way the cycle
    // needed 25 and 30; the Chebyshev smoothers 15 and 19, with strong connections only 11 and 14.)
    const Case small = lumpy_case(4), large = lumpy_case(6);
    const std::uint32_t n_small = iterations_to(small.problem, build_multigrid(small.problem), 1e-8);
    const std::uint32_t n_large = iterations_to(large.problem, build_multigrid(large.problem), 1e-8);
    std::printf("iterations to 1e-8 from zero: %u (2,562 vertices), %u (40,962 vertices)\n", n_small, n_large);
    EXPECT_LE(n_large, 16u);
    EXPECT_LE(n_large, n_small + n_small / 2);
}

TEST(SolversMultigrid, CoarsensRowsWithoutStrongNeighbours) {
    // Rows without a strong neighbour form no aggregate (the polycube map's pieces of one or two
    // free vertices): 300 of them make a dense level at once; 2,000 (a dense level would cost more
    // than the cycle) are paired by index until the level is small enough, and conjugate
    // gradients still converge at once. Every tenth row is coupled to the next, weakly.
    for (std::size_t rows : {300u, 2000u}) {
        SCOPED_TRACE(rows);
        ChartProblem p;
        p.free_vertices.resize(rows);
        p.row_offsets.assign(1, 0);
        p.diagonal.resize(rows);
        for (std::size_t i = 0; i < rows; ++i) {
            p.diagonal[i] = 2.0 + std::sin(double(i));
            if (i % 10 == 0 && i + 1 < rows) p.columns.push_back(std::uint32_t(i + 1)), p.values.push_back(-0.01);
            if (i % 10 == 1) p.columns.push_back(std::uint32_t(i - 1)), p.values.push_back(-0.01);
            p.row_offsets.push_back(std::uint32_t(p.columns.size()));
        }
        p.rhs = pseudo_random(rows, 0.3);
        p.start.assign(rows, glm::dvec2(0.0));
        const Multigrid mg = build_multigrid(p);
        if (rows > 1024) {
            EXPECT_GE(mg.levels.size(), 1u);
            EXPECT_LE(mg.coarsest_rows(), 1024u);
        } else {
            EXPECT_EQ(mg.coarsest_rows(), rows);
        }
        const std::uint32_t iterations = iterations_to(p, mg, 1e-10);
        std::printf("%zu rows, %zu levels: %u iterations to 1e-10\n", rows, mg.levels.size(), iterations);
        EXPECT_LE(iterations, 12u);
    }
}

TEST(SolversMultigrid, ConjugateGradientsReportABreakdownOnAnIndefiniteMatrix) {
    // [[1, -2], [-2, 1]] has the eigenvalues 3 and -1 (negative cotangent weights can make a polish
    // matrix indefinite). With b along the eigenvector of -1, r.z < 0 from the start: conjugate
    // gradients have broken down, and the residual must say so rather than read as converged.
    ChartProblem p;
    p.free_vertices = {0, 1};
    p.row_offsets = {0, 1, 2};
    p.columns = {1, 0};
    p.values = {-2.0, -2.0};
    p.diagonal = {1.0, 1.0};
    p.rhs.assign(2, glm::dvec2(1.0));
    p.start.assign(2, glm::dvec2(0.0));
    const Multigrid mg = build_multigrid(p);
    CgState state = start_cg(p, mg);
    EXPECT_LT(state.rz, 0.0);
    EXPECT_TRUE(std::isnan(state.relative_residual()));
    // A positive definite matrix with the same pattern converges, and its residual is a number.
    p.diagonal = {3.0, 3.0};
    const Multigrid spd = build_multigrid(p);
    state = start_cg(p, spd);
    EXPECT_GT(state.relative_residual(), 0.5);
    cg_cpu(spd, state, 2);
    EXPECT_LT(state.relative_residual(), 1e-12);
}

TEST(SolversMultigrid, ChecksComeWhenThePastRateSaysTheToleranceIsReached) {
    // 1e-2 -> 1e-4 in 8 iterations: a factor 10 every 4. To 1e-5: 4 more; to 1e-7: 12, at most 8.
    EXPECT_EQ(iterations_to_reach(1e-5, 1e-2, 1e-4, 8, 8), 4u);
    EXPECT_EQ(iterations_to_reach(1e-7, 1e-2, 1e-4, 8, 8), 8u);
    // 10^-0.7 further needs 2.8 iterations: 3 (odd counts too).
    EXPECT_EQ(iterations_to_reach(1e-4 * std::pow(10.0, -0.7), 1e-2, 1e-4, 8, 8), 3u);
    EXPECT_EQ(iterations_to_reach(0.99e-4, 1e-2, 1e-4, 8, 8), 1u);  // at least 1
    // No progress, a breakdown, or already there: a whole check.
    EXPECT_EQ(iterations_to_reach(1e-8, 1e-4, 1e-4, 8, 8), 8u);
    EXPECT_EQ(iterations_to_reach(1e-8, 1e-4, 2e-4, 8, 8), 8u);
    EXPECT_EQ(iterations_to_reach(1e-8, 1e-4, std::nan(""), 8, 8), 8u);
    EXPECT_EQ(iterations_to_reach(1e-3, 1e-2, 1e-4, 8, 8), 8u);
}

TEST_F(SolversMultigridGpu, TheGpuCycleIsItsCpuTwinToTheBit) {
    // The solvers compare whole solves; this holds each cycle to apply_multigrid_cpu's float
    // cycle exactly, on hierarchies of one, two and three smoothed levels.
    std::vector<std::size_t> depths;
    for (int subdivisions : {3, 5, 6}) {
        const Case c = lumpy_case(subdivisions);
        const Multigrid mg = build_multigrid(c.problem);
        depths.push_back(mg.levels.size());
        SCOPED_TRACE(mg.levels.size());
        GpuVcycle cycle(ctx(), mg, "test mg");
        for (double seed : {0.3, 1.1}) {
            const auto b = pseudo_random(mg.rows(), seed);
            const auto cpu = apply_multigrid_cpu(mg, b, CyclePrecision::float32);
            const auto gpu = gpu_cycle(ctx(), cycle, b);
            std::size_t differing = 0;
            for (std::size_t i = 0; i < b.size(); ++i) differing += glm::vec2(cpu[i]) != gpu[i];
            EXPECT_EQ(differing, 0u) << seed;
        }
    }
    EXPECT_EQ(depths, (std::vector<std::size_t>{1, 2, 3}));
}

// The sparse solvers (gimg/passes/solvers.h): conjugate gradients with multigrid for symmetric
// positive definite systems and BiCGSTAB for non-symmetric ones, on the GPU, their CPU twins and
// Eigen's direct solvers (SimplicialLDLT, SparseLU) of the same Dirichlet problems.
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/cotangent.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/solvers.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <random>

using namespace gimg;
using passes::LinearSystem;
using passes::SolveOptions;
using passes::SolveResult;
using passes::SparseMatrix;

namespace {

// A grid with its interior vertices jittered, so cotangent weights differ from edge to edge.
geo::Mesh jittered_grid(int n) {
    geo::Mesh mesh = geo::make_grid(n, n);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.25 / n, 0.25 / n);
    for (glm::dvec3& p : mesh.positions)
        if (p.x > 1e-9 && p.x < 1 - 1e-9 && p.y > 1e-9 && p.y < 1 - 1e-9) {
            p.x += jitter(rng);
            p.y += jitter(rng);
        }
    return mesh;
}

// L = D - W over all vertices: `weights` per edge of `adj` (cotangent or uniform), plus `shift` on
// the diagonal. With row_normalised, every row is divided by its diagonal (I - D^-1 W: Tutte's
// barycentric system with these weights, not symmetric).
SparseMatrix laplacian(const geo::MeshAdjacency& adj, const std::vector<double>& weights, double shift,
                       bool row_normalised) {
    const std::size_t n = adj.vertex_count();
    SparseMatrix a;
    a.size = n;
    for (std::uint32_t i = 0; i < n; ++i) {
        double diagonal = shift;
        std::vector<std::pair<std::uint32_t, double>> row;
        for (std::uint32_t j : adj.neighbors(i)) {
            const double w = weights[adj.find_edge(i, j)];
            diagonal += w;
            row.emplace_back(j, -w);
        }
        row.emplace_back(i, diagonal);
        for (auto [j, value] : row) {
            a.columns.push_back(j);
            a.values.push_back(row_normalised ? value / diagonal : value);
        }
        a.offsets.push_back(std::uint32_t(a.columns.size()));
    }
    return a;
}

// A known solution on every row; fixed rows keep theirs, b = A x on free rows (rows of A are
// only needed there).
LinearSystem system_with_solution(const SparseMatrix& a, std::vector<std::uint8_t> fixed, std::uint32_t k,
                                  std::vector<double>& truth) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    truth.resize(a.size * k);
    for (double& t : truth) t = u(rng);
    LinearSystem s;
    s.a = a;
    s.rhs_count = k;
    s.fixed = std::move(fixed);
    s.fixed_values = truth;
    s.b.assign(a.size * k, 0.0);
    for (std::size_t i = 0; i < a.size; ++i)
        for (std::uint32_t e = a.offsets[i]; e < a.offsets[i + 1]; ++e)
            for (std::uint32_t c = 0; c < k; ++c) s.b[i * k + c] += a.values[e] * truth[a.columns[e] * k + c];
    return s;
}

std::vector<std::uint8_t> boundary_fixed(const geo::MeshAdjacency& adj) {
    const std::vector<std::uint8_t> interior = adj.interior_vertices();
    std::vector<std::uint8_t> fixed(interior.size());
    for (std::size_t i = 0; i < fixed.size(); ++i) fixed[i] = interior[i] ? 0 : 1;
    return fixed;
}

// Eigen's direct solution of the same reduced system, column c.
std::vector<double> direct_solution(const LinearSystem& s, bool symmetric) {
    const std::size_t n = s.a.size, k = s.rhs_count;
    std::vector<int> index(n, -1);
    int m = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (!s.fixed[i]) index[i] = m++;
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(m, Eigen::Index(k));
    for (std::size_t i = 0; i < n; ++i) {
        if (index[i] < 0) continue;
        for (std::uint32_t c = 0; c < k; ++c) b(index[i], c) = s.b[i * k + c];
        for (std::uint32_t e = s.a.offsets[i]; e < s.a.offsets[i + 1]; ++e) {
            const std::uint32_t j = s.a.columns[e];
            if (index[j] >= 0)
                triplets.emplace_back(index[i], index[j], s.a.values[e]);
            else
                for (std::uint32_t c = 0; c < k; ++c) b(index[i], c) -= s.a.values[e] * s.fixed_values[j * k + c];
        }
    }
    Eigen::SparseMatrix<double> a(m, m);
    a.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::MatrixXd x;
    if (symmetric) {
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
        x = ldlt.solve(b);
    } else {
        Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
        lu.compute(a);
        x = lu.solve(b);
    }
    std::vector<double> out(s.fixed_values);
    for (std::size_t i = 0; i < n; ++i)
        if (index[i] >= 0)
            for (std::uint32_t c = 0; c < k; ++c) out[i * k + c] = x(index[i], c);
    return out;
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
    return d;
}

// Floater's shape-preserving weights of a jittered grid lifted to a bumpy height field, as the
// square map solves them: I - W on interior rows (not symmetric), the identity on boundary rows.
SparseMatrix floater_system(int n, geo::MeshAdjacency& adj) {
    geo::Mesh mesh = jittered_grid(n);
    for (glm::dvec3& p : mesh.positions) p.z = 0.2 * std::sin(6.0 * p.x) * std::cos(5.0 * p.y);
    adj = geo::build_adjacency(mesh);
    const std::vector<double> w = passes::floater_weights(mesh, adj);
    const std::vector<std::uint8_t> interior = adj.interior_vertices();
    SparseMatrix a;
    a.size = mesh.vertex_count();
    for (std::uint32_t i = 0; i < a.size; ++i) {
        a.columns.push_back(i);
        a.values.push_back(1.0);
        if (interior[i])
            for (std::uint32_t k = adj.vertex_vertex_offsets[i]; k < adj.vertex_vertex_offsets[i + 1]; ++k) {
                a.columns.push_back(adj.vertex_vertices[k]);
                a.values.push_back(-w[k]);
            }
        a.offsets.push_back(std::uint32_t(a.columns.size()));
    }
    return a;
}

class Solvers : public test::GpuTest {};

}  // namespace

TEST_F(Solvers, SymmetricEqualsTheCpuTwinAndEigensCholeskyOnACotangentLaplacian) {
    const geo::Mesh mesh = jittered_grid(40);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const SparseMatrix a = laplacian(adj, geo::cotangent_weights(mesh, adj), 0.0, false);
    for (std::uint32_t k : {1u, 2u, 3u, 4u}) {
        SCOPED_TRACE(k);
        std::vector<double> truth;
        const LinearSystem s = system_with_solution(a, boundary_fixed(adj), k, truth);
        const SolveResult gpu = passes::solve_symmetric(ctx(), s, {.tolerance = 1e-10});
        const SolveResult cpu = passes::solve_symmetric_cpu(s, {.tolerance = 1e-10});
        const std::vector<double> direct = direct_solution(s, true);
        std::printf("conjugate gradients, %u right-hand sides, %zu rows: %zu iterations to 1e-10\n", k, a.size,
                    gpu.iterations);
        EXPECT_TRUE(gpu.converged);
        EXPECT_LE(gpu.iterations, 40u);  // multigrid: flat in the mesh size
        EXPECT_EQ(gpu.iterations, cpu.iterations);
        EXPECT_LT(max_difference(gpu.x, cpu.x), 1e-10);
        EXPECT_LT(max_difference(gpu.x, direct), 1e-7);
        EXPECT_LT(max_difference(direct, truth), 1e-9);
        for (std::size_t i = 0; i < a.size; ++i) {  // fixed rows hold their values exactly
            if (s.fixed[i]) {
                EXPECT_EQ(gpu.x[i * k], truth[i * k]);
            }
        }
    }
}

TEST_F(Solvers, SymmetricOnASharedMeshWithScatteredDirichletRows) {
    const auto path = test::shared_mesh("bunny_small.obj");
    if (!path) GTEST_SKIP() << "shared meshes not found (set GIMG_MESH_DIR)";
    const geo::Mesh mesh = geo::load_mesh(*path);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const std::vector<double> uniform(adj.edge_count(), 1.0);
    const SparseMatrix a = laplacian(adj, uniform, 0.0, false);
    std::vector<std::uint8_t> fixed(a.size, 0);
    for (std::size_t i = 0; i < a.size; i += 50) fixed[i] = 1;
    std::vector<double> truth;
    const LinearSystem s = system_with_solution(a, fixed, 3, truth);
    const SolveResult gpu = passes::solve_symmetric(ctx(), s, {.tolerance = 1e-10});
    EXPECT_TRUE(gpu.converged);
    EXPECT_LT(max_difference(gpu.x, direct_solution(s, true)), 1e-7);
    EXPECT_LT(max_difference(gpu.x, truth), 1e-7);
}

TEST_F(Solvers, SymmetricOnManyPiecesOfOneOrTwoFreeVertices) {
    // 1,500 paths, each a fixed vertex, one or two free ones (one in five has two) and a fixed
    // vertex, weights 1 to 2 (the polycube map's pieces): 1,800 free rows in blocks of one or two,
    // which no aggregate joins. It used to stop the multigrid with "aggregation stalled".
    SparseMatrix a;
    std::vector<std::uint8_t> fixed;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> weight(1.0, 2.0);
    for (int piece = 0; piece < 1500; ++piece) {
        const std::uint32_t first = std::uint32_t(fixed.size()), free = piece % 5 == 0 ? 2 : 1;
        std::vector<double> w(free + 1);
        for (double& x : w) x = weight(rng);
        for (std::uint32_t k = 0; k < free + 2; ++k) {
            fixed.push_back(k == 0 || k == free + 1 ? 1 : 0);
            const double left = k > 0 ? w[k - 1] : 0.0, right = k <= free ? w[k] : 0.0;
            if (k > 0) a.columns.push_back(first + k - 1), a.values.push_back(-left);
            a.columns.push_back(first + k), a.values.push_back(left + right);
            if (k <= free) a.columns.push_back(first + k + 1), a.values.push_back(-right);
            a.offsets.push_back(std::uint32_t(a.columns.size()));
        }
    }
    a.size = fixed.size();
    std::vector<double> truth;
    const LinearSystem s = system_with_solution(a, fixed, 2, truth);
    const SolveResult gpu = passes::solve_symmetric(ctx(), s, {.tolerance = 1e-10});
    const SolveResult cpu = passes::solve_symmetric_cpu(s, {.tolerance = 1e-10});
    std::printf("conjugate gradients on 1,500 pieces: %zu iterations to 1e-10\n", gpu.iterations);
    EXPECT_TRUE(gpu.converged);
    EXPECT_LE(gpu.iterations, 20u);
    EXPECT_EQ(gpu.iterations, cpu.iterations);
    EXPECT_LT(max_difference(gpu.x, cpu.x), 1e-10);
    EXPECT_LT(max_difference(gpu.x, truth), 1e-8);
}

TEST_F(Solvers, GeneralEqualsTheCpuTwinAndEigensLuOnRowNormalisedWeights) {
    // Tutte's system with cotangent weights divided by their row sums: not symmetric.
    const geo::Mesh mesh = jittered_grid(30);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const SparseMatrix a = laplacian(adj, geo::cotangent_weights(mesh, adj), 0.0, true);
    for (passes::Preconditioner preconditioner : {passes::Preconditioner::Jacobi, passes::Preconditioner::Multigrid}) {
        for (std::uint32_t k : {1u, 2u, 3u}) {
            const bool jacobi = preconditioner == passes::Preconditioner::Jacobi;
            SCOPED_TRACE(std::string(jacobi ? "Jacobi, " : "multigrid, ") + std::to_string(k));
            std::vector<double> truth;
            const LinearSystem s = system_with_solution(a, boundary_fixed(adj), k, truth);
            const SolveOptions o{.tolerance = 1e-11,
                                 .max_iterations = 2000,
                                 .iterations_per_check = 10,
                                 .preconditioner = preconditioner};
            const SolveResult gpu = passes::solve_general(ctx(), s, o);
            const SolveResult cpu = passes::solve_general_cpu(s, o);
            const std::vector<double> direct = direct_solution(s, false);
            std::printf("BiCGSTAB (%s), %u right-hand sides, %zu rows: %zu iterations to 1e-11, CPU twin %zu\n",
                        jacobi ? "Jacobi" : "multigrid", k, a.size, gpu.iterations, cpu.iterations);
            EXPECT_TRUE(gpu.converged) << gpu.residual;
            EXPECT_TRUE(cpu.converged) << cpu.residual;
            // Both stop at the first check whose residual is under the tolerance: with the cycle
            // (about 24 iterations) within one check of each other, the GPU's sums rounding
            // differently. Jacobi's residual here rises and falls, and a rise amplifies rounding:
            // the GPU's and the CPU's x part by 1e-11 after 20 iterations and by 1e-5 after 30
            // (with either order of the GPU's sums), so where each first dips under 1e-11 is not
            // comparable (91-103 iterations).
            if (!jacobi) {
                EXPECT_LE(std::max(gpu.iterations, cpu.iterations) - std::min(gpu.iterations, cpu.iterations),
                          o.iterations_per_check);
            }
            EXPECT_LT(max_difference(gpu.x, cpu.x), 1e-8);
            EXPECT_LT(max_difference(gpu.x, direct), 1e-8);
            EXPECT_LT(max_difference(direct, truth), 1e-9);
        }
    }
}

TEST_F(Solvers, GeneralFollowsItsCpuTwinIterationByIteration) {
    // Jacobi on a 12 x 12 grid; the multigrid cycle on 30 x 30 (784 free rows: the hierarchy has
    // smoothed levels above its dense one).
    struct Case {
        int grid;
        passes::Preconditioner preconditioner;
        std::vector<std::size_t> iterations;
    };
    for (const Case& c : {Case{12, passes::Preconditioner::Jacobi, {1, 3, 7}},
                          Case{30, passes::Preconditioner::Multigrid, {1, 2, 5}}}) {
        const geo::Mesh mesh = jittered_grid(c.grid);
        const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
        const SparseMatrix a = laplacian(adj, geo::cotangent_weights(mesh, adj), 0.0, true);
        std::vector<double> truth;
        const LinearSystem s = system_with_solution(a, boundary_fixed(adj), 2, truth);
        for (std::size_t iterations : c.iterations) {
            const SolveOptions o{.tolerance = 0.0,
                                 .max_iterations = iterations,
                                 .iterations_per_check = 100,
                                 .preconditioner = c.preconditioner};
            const SolveResult gpu = passes::solve_general(ctx(), s, o);
            const SolveResult cpu = passes::solve_general_cpu(s, o);
            EXPECT_EQ(gpu.iterations, iterations);
            EXPECT_LT(max_difference(gpu.x, cpu.x), 1e-12) << c.grid << " grid, " << iterations << " iterations";
            EXPECT_NEAR(gpu.residual, cpu.residual, 1e-12 + 1e-9 * cpu.residual);
        }
    }
}

TEST_F(Solvers, GeneralWithTheMultigridCycleNeedsFarFewerIterationsThanJacobi) {
    // Floater's system on 3,364 free rows, to 1e-10: Jacobi's iterations grow with the rings across,
    // the cycle's do not.
    geo::MeshAdjacency adj;
    const SparseMatrix a = floater_system(60, adj);
    std::vector<double> truth;
    const LinearSystem s = system_with_solution(a, boundary_fixed(adj), 2, truth);
    const SolveOptions jacobi{.tolerance = 1e-10, .max_iterations = 5000, .iterations_per_check = 4};
    SolveOptions multigrid = jacobi;
    multigrid.preconditioner = passes::Preconditioner::Multigrid;
    const SolveResult by_jacobi = passes::solve_general_cpu(s, jacobi);
    const SolveResult cpu = passes::solve_general_cpu(s, multigrid);
    const SolveResult gpu = passes::solve_general(ctx(), s, multigrid);
    std::printf("BiCGSTAB to 1e-10 on %zu rows: Jacobi %zu iterations, multigrid %zu (GPU %zu)\n", a.size,
                by_jacobi.iterations, cpu.iterations, gpu.iterations);
    ASSERT_TRUE(by_jacobi.converged && cpu.converged && gpu.converged);
    EXPECT_LE(5 * cpu.iterations, by_jacobi.iterations);
    EXPECT_LE(std::max(gpu.iterations, cpu.iterations) - std::min(gpu.iterations, cpu.iterations),
              multigrid.iterations_per_check);
    const std::vector<double> direct = direct_solution(s, false);
    EXPECT_LT(max_difference(cpu.x, direct), 1e-8);
    EXPECT_LT(max_difference(gpu.x, direct), 1e-8);
}

TEST_F(Solvers, GeneralKeepsTheUploadedCycleInItsCacheAndGivesTheSameSolution) {
    // A run of solves with one cache uploads the hierarchy once: it stays allocated between solves,
    // a second solve allocates no more, clear() frees it, and each solve equals an uncached one.
    geo::MeshAdjacency adj;
    const SparseMatrix a = floater_system(30, adj);
    std::vector<double> truth;
    const LinearSystem s = system_with_solution(a, boundary_fixed(adj), 2, truth);
    const SolveOptions plain{.tolerance = 1e-10,
                             .max_iterations = 500,
                             .iterations_per_check = 4,
                             .preconditioner = passes::Preconditioner::Multigrid};
    const SolveResult alone = passes::solve_general(ctx(), s, plain);
    passes::PreconditionerCache cache;
    SolveOptions cached = plain;
    cached.reuse = &cache;
    const std::uint64_t before = ctx().memory_stats().allocated_bytes;
    const SolveResult first = passes::solve_general(ctx(), s, cached);
    const std::uint64_t kept = ctx().memory_stats().allocated_bytes;
    const SolveResult second = passes::solve_general(ctx(), s, cached);
    EXPECT_GT(kept, before) << "the hierarchy's images are kept";
    EXPECT_EQ(ctx().memory_stats().allocated_bytes, kept) << "and not uploaded again";
    cache.clear();
    EXPECT_EQ(ctx().memory_stats().allocated_bytes, before);
    for (const SolveResult* r : {&first, &second}) {
        EXPECT_EQ(r->iterations, alone.iterations);
        EXPECT_EQ(max_difference(r->x, alone.x), 0.0);
    }
}

TEST_F(Solvers, GeneralWithTheMultigridCycleFallsBackToJacobiOnADiagonalMatrix) {
    // 1,100 rows and no off-diagonal entry: nothing to aggregate, so Jacobi, which solves it at once.
    const std::size_t n = 1100;
    LinearSystem s;
    s.a.size = n;
    for (std::uint32_t i = 0; i < n; ++i) {
        s.a.columns.push_back(i);
        s.a.values.push_back(1.0 + i % 7);
        s.a.offsets.push_back(i + 1);
        s.b.push_back(double(i % 5));
    }
    const SolveOptions o{.tolerance = 1e-12, .preconditioner = passes::Preconditioner::Multigrid};
    for (const SolveResult& r : {passes::solve_general(ctx(), s, o), passes::solve_general_cpu(s, o)}) {
        ASSERT_TRUE(r.converged);
        for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(r.x[i], double(i % 5) / (1.0 + i % 7), 1e-12);
    }
}

TEST_F(Solvers, ClearErrorsForUnfitSystems) {
    const geo::Mesh mesh = jittered_grid(6);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const SparseMatrix nonsymmetric = laplacian(adj, geo::cotangent_weights(mesh, adj), 0.0, true);
    std::vector<double> truth;
    const LinearSystem s = system_with_solution(nonsymmetric, boundary_fixed(adj), 1, truth);
    try {
        passes::solve_symmetric(ctx(), s);
        ADD_FAILURE() << "a non-symmetric matrix was accepted";
    } catch (const geo::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("not symmetric"), std::string::npos) << e.what();
    }
    LinearSystem bad = s;
    bad.a.columns[3] = std::uint32_t(bad.a.size + 5);
    EXPECT_THROW(passes::solve_general(ctx(), bad), geo::InputError);
    bad = s;
    bad.b.pop_back();
    EXPECT_THROW(passes::solve_general_cpu(bad), geo::InputError);
    bad = s;
    bad.rhs_count = 5;
    EXPECT_THROW(passes::solve_general_cpu(bad), geo::InputError);
    // [[1, -2], [-2, 1]]: symmetric, eigenvalues 3 and -1. b along the eigenvector of -1.
    LinearSystem indefinite;
    indefinite.a = {2, {0, 2, 4}, {0, 1, 0, 1}, {1.0, -2.0, -2.0, 1.0}};
    indefinite.b = {1.0, 1.0};
    try {
        passes::solve_symmetric(ctx(), indefinite);
        ADD_FAILURE() << "an indefinite matrix converged";
    } catch (const geo::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("broke down"), std::string::npos) << e.what();
    }
    LinearSystem zero_diagonal;
    zero_diagonal.a = {2, {0, 1, 2}, {1, 0}, {1.0, 1.0}};
    zero_diagonal.b = {1.0, 2.0};
    EXPECT_THROW(passes::solve_general(ctx(), zero_diagonal), geo::InputError);
}

// A = [[1, 3/2, 0], [0, 1, 2], [-2, 0, 1]], b = (0, -2, 0): BiCGSTAB's first step leaves the
// residual (2.4, 0, 1.2) exactly orthogonal to the shadow residual r0 = b, where it cannot go on
// (this threw "broke down"); started again from there it reaches x = (-0.6, 0.4, -1.2).
TEST_F(Solvers, GeneralStartsAgainWhereTheResidualTurnsOrthogonalToTheShadow) {
    LinearSystem s;
    s.a = {3, {0, 2, 4, 6}, {0, 1, 1, 2, 0, 2}, {1.0, 1.5, 1.0, 2.0, -2.0, 1.0}};
    s.b = {0.0, -2.0, 0.0};
    const std::vector<double> truth{-0.6, 0.4, -1.2};
    passes::SolveOptions o;
    o.iterations_per_check = 1;
    for (bool gpu : {false, true}) {
        const passes::SolveResult r = gpu ? passes::solve_general(ctx(), s, o) : passes::solve_general_cpu(s, o);
        EXPECT_TRUE(r.converged) << (gpu ? "GPU" : "CPU");
        for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(r.x[i], truth[i], 1e-9) << (gpu ? "GPU " : "CPU ") << i;
    }
}

TEST_F(Solvers, GeneralWithTheMultigridCycleSolvesAShiftedSystemWithoutFixedRows) {
    // I - W + a shift on every row, nothing fixed: the Laplacian of the symmetric part alone would
    // be singular; the cycle's Laplacian keeps each row's excess over diagonal dominance.
    const geo::Mesh mesh = jittered_grid(40);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const SparseMatrix a = laplacian(adj, std::vector<double>(adj.edge_count(), 1.0), 0.05, true);
    std::vector<double> truth;
    const LinearSystem s = system_with_solution(a, std::vector<std::uint8_t>(a.size, 0), 2, truth);
    const SolveOptions jacobi{.tolerance = 1e-10, .max_iterations = 3000, .iterations_per_check = 4};
    SolveOptions multigrid = jacobi;
    multigrid.preconditioner = passes::Preconditioner::Multigrid;
    const SolveResult by_jacobi = passes::solve_general_cpu(s, jacobi);
    for (const SolveResult& r : {passes::solve_general(ctx(), s, multigrid), passes::solve_general_cpu(s, multigrid)}) {
        ASSERT_TRUE(r.converged) << r.residual;
        EXPECT_LT(max_difference(r.x, truth), 1e-8);
        EXPECT_LT(2 * r.iterations, by_jacobi.iterations);
    }
}

namespace {

// |b - A x| / |b| over the free rows and every right-hand side.
double relative_residual(const LinearSystem& s, const std::vector<double>& x) {
    const std::size_t k = s.rhs_count;
    double rr = 0.0, bb = 0.0;
    for (std::size_t i = 0; i < s.a.size; ++i) {
        if (s.fixed[i]) continue;
        for (std::size_t c = 0; c < k; ++c) {
            double r = s.b[i * k + c];
            for (std::uint32_t e = s.a.offsets[i]; e < s.a.offsets[i + 1]; ++e)
                r -= s.a.values[e] * x[s.a.columns[e] * k + c];
            rr += r * r;
            bb += s.b[i * k + c] * s.b[i * k + c];
        }
    }
    return std::sqrt(rr / bb);
}

}  // namespace

TEST_F(Solvers, ProjectedStartRecoversASolutionQuadraticInTheRunsParameter) {
    // x(t) = x0 + t x1 + t^2 x2 on the free rows, one matrix: x(3) = x(2) - (x(2) - x(0)) + 3 (x(2) -
    // x(1)) lies in the span project_start searches, so from x(0), x(1), x(2) it starts at x(3).
    geo::MeshAdjacency adj;
    const SparseMatrix a = floater_system(30, adj);
    std::vector<double> x0, x1, x2;
    LinearSystem s = system_with_solution(a, boundary_fixed(adj), 2, x0);
    system_with_solution(a, boundary_fixed(adj), 2, x1);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    x2.resize(x0.size());
    for (double& v : x2) v = u(rng);
    auto at = [&](double t) {
        std::vector<double> x(x0.size());
        for (std::size_t i = 0; i < a.size; ++i)
            for (std::size_t c = 0; c < 2; ++c) {
                const std::size_t k = i * 2 + c;
                x[k] = s.fixed[i] ? x0[k] : x0[k] + t * x1[k] + t * t * x2[k];
            }
        return x;
    };
    const std::vector<double> truth = at(3.0);
    std::fill(s.b.begin(), s.b.end(), 0.0);
    for (std::size_t i = 0; i < a.size; ++i)
        for (std::uint32_t e = a.offsets[i]; e < a.offsets[i + 1]; ++e)
            for (std::size_t c = 0; c < 2; ++c) s.b[i * 2 + c] += a.values[e] * truth[a.columns[e] * 2 + c];

    passes::project_start(s, {at(2.0)});
    const double from_last = relative_residual(s, s.start);
    EXPECT_EQ(s.start, at(2.0));
    passes::project_start(s, {at(1.0), at(2.0)});
    const double linear = relative_residual(s, s.start);
    passes::project_start(s, {at(0.0), at(1.0), at(2.0)});
    const double quadratic = relative_residual(s, s.start);
    std::printf("start's relative residual: last solution %.3g, one step %.3g, two steps %.3g\n", from_last, linear,
                quadratic);
    EXPECT_GT(from_last, 1e-2);
    EXPECT_LT(linear, 0.5 * from_last);
    EXPECT_LT(quadratic, 1e-10);
    EXPECT_LT(max_difference(s.start, truth), 1e-8);
    const SolveOptions options{.tolerance = 1e-9, .preconditioner = passes::Preconditioner::Multigrid};
    EXPECT_EQ(passes::solve_general_cpu(s, options).iterations, 0u);
    EXPECT_EQ(passes::solve_general(ctx(), s, options).iterations, 0u);
}

TEST_F(Solvers, ProjectedStartOnADriftingMatrixLeavesATenthOfTheLastSolutionsResidual) {
    // Solutions of three systems whose weights drift, as reweighting iterations do: the fourth
    // system's start from their best combination has 80 times less residual than the last solution.
    geo::MeshAdjacency adj;
    const SparseMatrix base = floater_system(30, adj);
    std::vector<double> truth;
    const LinearSystem original = system_with_solution(base, boundary_fixed(adj), 2, truth);
    // Each weight moves by 10 % of its own random slope a step; rows stay normalised (1 - sum w = 0).
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> slope(original.a.values.size());
    for (double& g : slope) g = u(rng);
    auto drifted = [&](int steps) {
        LinearSystem s = original;
        for (std::size_t i = 0; i < s.a.size; ++i) {
            if (s.fixed[i]) continue;
            double sum = 0.0;
            for (std::uint32_t e = s.a.offsets[i]; e < s.a.offsets[i + 1]; ++e)
                if (s.a.columns[e] != i) {
                    s.a.values[e] *= 1.0 + 0.1 * steps * slope[e];
                    sum -= s.a.values[e];
                }
            for (std::uint32_t e = s.a.offsets[i]; e < s.a.offsets[i + 1]; ++e)
                if (s.a.columns[e] != i) s.a.values[e] /= sum;
        }
        return s;
    };
    const SolveOptions options{
        .tolerance = 1e-10, .iterations_per_check = 1, .preconditioner = passes::Preconditioner::Multigrid};
    std::vector<std::vector<double>> past;
    for (int t = 0; t < 3; ++t) past.push_back(passes::solve_general_cpu(drifted(t), options).x);
    LinearSystem next = drifted(3);
    passes::project_start(next, past);
    const double projected = relative_residual(next, next.start);
    const double last = relative_residual(next, past.back());
    std::printf("drifting matrix: start's relative residual %.3g projected, %.3g from the last solution\n", projected,
                last);
    EXPECT_LT(projected, 0.1 * last);
    LinearSystem plain = next;
    plain.start = past.back();
    const SolveResult from_projected = passes::solve_general_cpu(next, options);
    const SolveResult from_last = passes::solve_general_cpu(plain, options);
    std::printf("iterations to 1e-10: %zu from the projected start, %zu from the last solution\n",
                from_projected.iterations, from_last.iterations);
    EXPECT_LT(from_projected.iterations, from_last.iterations);

    std::vector<double> short_one = past.back();
    short_one.pop_back();
    EXPECT_THROW(passes::project_start(next, {past.back(), short_one}), geo::InputError);
}

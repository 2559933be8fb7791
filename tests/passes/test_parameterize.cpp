// Square maps of disk meshes and their geometry images: planar cases that must map to themselves,
// the GPU solve against its CPU twin and Eigen's SparseLU, fold-freedom on the shared disk meshes,
// the density iteration's monotone evening-out, and the image grid on the boundary.
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/parameterize.h"

#include <Eigen/SparseLU>

#include <cmath>
#include <numbers>

using namespace gimg;
using passes::ParameterizeVariant;

namespace {

class Parameterize : public gimg::test::GpuTest {};

double max_distance(const std::vector<glm::dvec2>& uv, const geo::Mesh& mesh) {
    double worst = 0.0;
    for (std::size_t i = 0; i < uv.size(); ++i)
        worst = std::max(worst, glm::length(uv[i] - glm::dvec2(mesh.positions[i].x, mesh.positions[i].y)));
    return worst;
}

// A unit-square grid with its interior vertices moved within the plane (the boundary stays put).
geo::Mesh jittered_grid(int n) {
    geo::Mesh m = geo::make_grid(n, n);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        glm::dvec3& p = m.positions[i];
        if (p.x > 0.0 && p.x < 1.0 && p.y > 0.0 && p.y < 1.0)
            p += 0.3 / n * glm::dvec3(std::sin(7.0 * double(i)), std::cos(11.0 * double(i)), 0.0);
    }
    return m;
}

// A grid bent into a quarter cylinder with a bump: a curved disk whose Floater weights are not symmetric.
geo::Mesh bent_grid(int n) {
    geo::Mesh m = geo::make_grid(n, n);
    for (auto& p : m.positions) {
        const double a = 0.5 * std::numbers::pi * p.x;
        const double bump = 0.2 * std::exp(-20.0 * ((p.x - 0.6) * (p.x - 0.6) + (p.y - 0.4) * (p.y - 0.4)));
        p = {(1.0 + bump) * std::cos(a), p.y, (1.0 + bump) * std::sin(a)};
    }
    m.texcoords.clear();
    return m;
}

}  // namespace

TEST_F(Parameterize, APlanarSquareGridMapsToItself) {
    // The density variant is left out: its corner factor x4 assumes a corner's one-ring is a quarter
    // of an interior one, which no grid of split squares has (a corner with one triangle has an
    // eighth of an interior vertex's area, with two a third), so it moves the grid near a corner.
    const geo::Mesh grid = geo::make_grid(8, 8);
    for (auto variant : {ParameterizeVariant::Tutte, ParameterizeVariant::Floater, ParameterizeVariant::Stretch,
                         ParameterizeVariant::Uniform3d, ParameterizeVariant::Curvature})
        for (const bool gpu : {false, true}) {
            passes::ParameterizeOptions o{.variant = variant, .solve_tolerance = 1e-12};
            const passes::Parameterization map = passes::parameterize_square(gpu ? &ctx() : nullptr, grid, o);
            EXPECT_LE(max_distance(map.uv, grid), 1e-9) << passes::variant_name(variant) << (gpu ? " gpu" : " cpu");
            EXPECT_EQ(map.boundary.corners, (std::array<std::uint32_t, 4>{0, 8, 80, 72}));
            EXPECT_LE(map.iterations.size(), 3u) << passes::variant_name(variant);  // nothing to reweigh
        }
}

TEST_F(Parameterize, CornersMoveToNearbyEarsSoThatNoFaceLiesFlatOnASide) {
    // A 1.2 x 1 grid: the quarter points of its perimeter (4.4) fall 0.1 short of two of its corners,
    // one grid step. A corner holding a single triangle (an ear) that is not a square's corner lies
    // flat on a side, and no sample of the image would fall on it.
    const geo::Mesh grid = geo::make_grid(12, 10, 1.2, 1.0);
    const geo::MeshAdjacency adj = geo::build_adjacency(grid);
    std::vector<std::uint32_t> ears;  // rectangle corners with one triangle
    for (std::uint32_t v = 0; v < grid.vertex_count(); ++v) {
        const glm::dvec3 p = grid.positions[v];
        const bool corner = (p.x < 1e-9 || p.x > 1.2 - 1e-9) && (p.y < 1e-9 || p.y > 1.0 - 1e-9);
        std::size_t faces = 0;
        for (const glm::uvec3& t : grid.triangles) faces += t.x == v || t.y == v || t.z == v;
        if (corner && faces == 1) ears.push_back(v);
    }
    ASSERT_EQ(ears.size(), 2u);
    const passes::SquareBoundary boundary = passes::square_boundary(grid, adj);
    for (std::uint32_t e : ears)
        EXPECT_NE(std::find(boundary.corners.begin(), boundary.corners.end(), e), boundary.corners.end())
            << "ear " << e << " at (" << grid.positions[e].x << ", " << grid.positions[e].y << ")";
    const passes::Parameterization map =
        passes::parameterize_square(nullptr, grid, {.variant = ParameterizeVariant::Floater});
    double smallest = 1.0;
    for (const glm::uvec3& t : grid.triangles) {
        const glm::dvec2 a = map.uv[t.x], b = map.uv[t.y], c = map.uv[t.z];
        smallest = std::min(smallest, 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)));
    }
    // Every face keeps at least a tenth of a cell of the 12 x 10 grid mapped to the square.
    EXPECT_GT(smallest, 0.1 * 0.5 / 120.0);
}

TEST_F(Parameterize, CornersFindASquarePatchsCornersWhateverItsNumbering) {
    // An 8 x 8 grid renumbered so that its smallest boundary index lies mid-side: the four corners
    // a quarter of the perimeter apart that turn the most are the grid's, and Floater's map is the
    // grid itself turned about the square (every face keeps its area).
    const geo::Mesh grid = geo::make_grid(8, 8);
    const std::uint32_t count = std::uint32_t(grid.vertex_count()), shift = 4;
    geo::Mesh renumbered;
    renumbered.positions.resize(count);
    for (std::uint32_t v = 0; v < count; ++v) renumbered.positions[(v + count - shift) % count] = grid.positions[v];
    for (const glm::uvec3& t : grid.triangles)
        renumbered.triangles.push_back((t + glm::uvec3(count - shift)) % glm::uvec3(count));
    ASSERT_GT(renumbered.positions[0].x, 0.0);  // vertex 0 is no longer a corner
    const passes::Parameterization map =
        passes::parameterize_square(nullptr, renumbered, {.variant = ParameterizeVariant::Floater});
    for (std::uint32_t c : map.boundary.corners) {
        const glm::dvec3 p = renumbered.positions[c];
        EXPECT_TRUE((p.x == 0.0 || p.x == 1.0) && (p.y == 0.0 || p.y == 1.0))
            << "corner " << c << " at " << p.x << ", " << p.y;
    }
    double worst = 0.0;
    for (const glm::uvec3& t : renumbered.triangles) {
        const glm::dvec2 a = map.uv[t.x], b = map.uv[t.y], c = map.uv[t.z];
        const glm::dvec3 pa = renumbered.positions[t.x], pb = renumbered.positions[t.y], pc = renumbered.positions[t.z];
        const double uv_area = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
        const double area = 0.5 * ((pb.x - pa.x) * (pc.y - pa.y) - (pb.y - pa.y) * (pc.x - pa.x));
        worst = std::max(worst, std::abs(uv_area - area));
    }
    EXPECT_LT(worst, 1e-9);
}

TEST_F(Parameterize, FloatersWeightsReproduceAPlanarMesh) {
    const geo::Mesh grid = jittered_grid(9);
    const geo::MeshAdjacency adj = geo::build_adjacency(grid);
    const std::vector<double> w = passes::floater_weights(grid, adj);
    const std::vector<std::uint8_t> interior = adj.interior_vertices();
    for (std::size_t i = 0; i < grid.vertex_count(); ++i) {
        if (!interior[i]) continue;
        double sum = 0.0;
        glm::dvec3 mean(0.0);
        const auto nb = adj.neighbors(i);
        for (std::size_t k = 0; k < nb.size(); ++k) {
            const double wk = w[adj.vertex_vertex_offsets[i] + k];
            EXPECT_GT(wk, 0.0);
            sum += wk;
            mean += wk * grid.positions[nb[k]];
        }
        EXPECT_NEAR(sum, 1.0, 1e-12);
        EXPECT_LE(glm::length(mean - grid.positions[i]), 1e-12) << "vertex " << i;
    }
    const passes::Parameterization map =
        passes::parameterize_square(nullptr, grid, {.variant = ParameterizeVariant::Floater, .solve_tolerance = 1e-12});
    EXPECT_LE(max_distance(map.uv, grid), 1e-9);
}

TEST(ParameterizeInput, RefusesWhatIsNotADisk) {
    auto refusal = [](const geo::Mesh& m) {
        try {
            passes::check_disk_mesh(m);
        } catch (const geo::InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(refusal(geo::make_box({1, 1, 1}, 2)).find("closed"), std::string::npos);
    geo::Mesh two = geo::make_grid(3, 3);
    const geo::Mesh other = geo::make_grid(3, 3);
    const auto offset = std::uint32_t(two.positions.size());
    for (auto p : other.positions) two.positions.push_back(p + glm::dvec3(2, 0, 0));
    for (auto t : other.triangles) two.triangles.push_back(t + offset);
    two.texcoords.clear();
    EXPECT_NE(refusal(two).find("2 components"), std::string::npos);
    geo::Mesh annulus = geo::make_grid(5, 5);
    std::erase_if(annulus.triangles, [&](const glm::uvec3& t) {
        const glm::dvec3 c = (annulus.positions[t.x] + annulus.positions[t.y] + annulus.positions[t.z]) / 3.0;
        return std::abs(c.x - 0.5) < 0.1 && std::abs(c.y - 0.5) < 0.1;  // the middle square
    });
    EXPECT_NE(refusal(annulus).find("2 boundary loops"), std::string::npos) << refusal(annulus);
    EXPECT_EQ(refusal(geo::make_grid(3, 3)), "accepted");
    EXPECT_THROW(passes::parameterize_square(nullptr, annulus), geo::InputError);
}

TEST_F(Parameterize, GpuSolveEqualsItsCpuTwinAndSparseLU) {
    const geo::Mesh mesh = bent_grid(24);
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const passes::SquareBoundary boundary = passes::square_boundary(mesh, adj);
    const std::vector<double> w = passes::floater_weights(mesh, adj);
    // The same system by a direct solver: interior rows u_i - sum w_ij u_j = 0, boundary rows fixed.
    const std::size_t n = mesh.vertex_count();
    std::vector<int> fixed(n, -1);
    for (std::size_t k = 0; k < boundary.loop.size(); ++k) fixed[boundary.loop[k]] = int(k);
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(Eigen::Index(n), 2);
    for (std::size_t i = 0; i < n; ++i) {
        entries.emplace_back(int(i), int(i), 1.0);
        if (fixed[i] >= 0) {
            rhs(Eigen::Index(i), 0) = boundary.uv[std::size_t(fixed[i])].x;
            rhs(Eigen::Index(i), 1) = boundary.uv[std::size_t(fixed[i])].y;
            continue;
        }
        const auto nb = adj.neighbors(i);
        for (std::size_t k = 0; k < nb.size(); ++k)
            entries.emplace_back(int(i), int(nb[k]), -w[adj.vertex_vertex_offsets[i] + k]);
    }
    Eigen::SparseMatrix<double> a{Eigen::Index(n), Eigen::Index(n)};
    a.setFromTriplets(entries.begin(), entries.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(a);
    ASSERT_EQ(lu.info(), Eigen::Success);
    const Eigen::MatrixXd direct = lu.solve(rhs);

    const passes::ParameterizeOptions floater{.variant = ParameterizeVariant::Floater, .solve_tolerance = 1e-12};
    const auto gpu = passes::parameterize_square(&ctx(), mesh, floater);
    const auto cpu = passes::parameterize_square(nullptr, mesh, floater);
    double gpu_cpu = 0.0, cpu_lu = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        gpu_cpu = std::max(gpu_cpu, glm::length(gpu.uv[i] - cpu.uv[i]));
        cpu_lu = std::max(cpu_lu,
                          glm::length(cpu.uv[i] - glm::dvec2(direct(Eigen::Index(i), 0), direct(Eigen::Index(i), 1))));
    }
    EXPECT_LE(gpu_cpu, 1e-10);
    EXPECT_LE(cpu_lu, 1e-9);
    EXPECT_GT(cpu_lu, 0.0);  // a different solver, not the same numbers by accident

    // Reweighted (non-symmetric, changing) systems, each solve warm-started: the paths stay together.
    const passes::ParameterizeOptions density{.variant = ParameterizeVariant::Curvature,
                                              .max_iterations = 4,
                                              .solve_tolerance = 1e-12,
                                              .iterate_tolerance = 1e-12};
    const auto gpu4 = passes::parameterize_square(&ctx(), mesh, density);
    const auto cpu4 = passes::parameterize_square(nullptr, mesh, density);
    ASSERT_EQ(gpu4.iterations.size(), cpu4.iterations.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, glm::length(gpu4.uv[i] - cpu4.uv[i]));
    EXPECT_LE(worst, 1e-9);
}

TEST_F(Parameterize, LooseIteratesAndOneFullSolveGiveTheMapWithFewerSolverIterations) {
    // The reweighting's iterates solved to 1e-5 and the returned weights once more to 1e-8, against
    // every iterate to 1e-8: the same map to a thousandth of the square (under a pixel of any image
    // up to 1000 x 1000), fold-free, and for a run of many iterations (curvature) fewer solver
    // iterations in all. Yoshizawa's run stops after two iterations here, each started from the
    // projection of the last maps, and the final solve costs about what the loose iterates save
    // (16 against 15); on the shared meshes it saves there too (mannequin_devil 91 against 144).
    const geo::Mesh mesh = bent_grid(48);
    for (auto variant : {ParameterizeVariant::Curvature, ParameterizeVariant::Stretch}) {
        SCOPED_TRACE(passes::variant_name(variant));
        const passes::Parameterization tight =
            passes::parameterize_square(nullptr, mesh, {.variant = variant, .iterate_tolerance = 1e-8});
        const passes::Parameterization loose = passes::parameterize_square(nullptr, mesh, {.variant = variant});
        auto total = [](const passes::Parameterization& m) {
            std::size_t sum = m.final_solver_iterations;
            for (const auto& r : m.iterations) sum += r.solver_iterations;
            return sum;
        };
        EXPECT_EQ(tight.final_solver_iterations, 0u);
        EXPECT_GT(loose.final_solver_iterations, 0u);
        if (variant == ParameterizeVariant::Curvature) {
            EXPECT_LT(total(loose), total(tight));
        }
        double worst = 0.0;
        for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
            worst = std::max(worst, glm::length(loose.uv[i] - tight.uv[i]));
        std::printf("%s: %zu solver iterations against %zu, maps %.2e apart\n", passes::variant_name(variant),
                    total(loose), total(tight), worst);
        EXPECT_LT(worst, 1e-3);
        EXPECT_EQ(passes::count_flipped(mesh, loose.uv), 0u);
    }
}

// The solves' share of the time: within each iteration's and the run's, on both paths; the GPU path's
// submissions and waits, none on the CPU twin.
TEST_F(Parameterize, SolveTimesArePartOfTheIterationsTimesAndTheGpuPathCountsItsSubmissions) {
    const geo::Mesh mesh = bent_grid(24);
    for (gimg::Context* c : {&ctx(), static_cast<gimg::Context*>(nullptr)}) {
        SCOPED_TRACE(c ? "GPU" : "CPU twin");
        const passes::Parameterization map = passes::parameterize_square(c, mesh, {});
        ASSERT_GT(map.iterations.size(), 1u);
        ASSERT_GT(map.final_solver_iterations, 0u);
        double iterations = 0.0;
        for (const passes::IterationReport& r : map.iterations) {
            EXPECT_GT(r.solve_seconds, 0.0);
            EXPECT_LE(r.solve_seconds, r.seconds);
            iterations += r.solve_seconds;
        }
        EXPECT_GT(map.solve_seconds, iterations);  // and the final solve
        EXPECT_LT(map.solve_seconds, map.seconds);
        if (c) {
            // At least a submission per solve: the iterations' solves and the final one.
            EXPECT_GE(map.submissions, map.iterations.size() + 1);
            EXPECT_LT(map.device_wait_seconds, map.seconds);
        } else {
            EXPECT_EQ(map.submissions, 0u);
            EXPECT_EQ(map.device_wait_seconds, 0.0);
        }
    }
}

TEST_F(Parameterize, EveryVariantIsFoldFreeOnTheSharedDiskMeshes) {
    for (const char* name :
         {"nefertiti.off", "terrain.obj", "three_peaks.off", "mushroom.off", "mannequin_devil.off"}) {
        GIMG_REQUIRE_SHARED_MESH(path, name);
        const geo::Mesh mesh = geo::load_mesh(path);
        for (auto variant :
             {ParameterizeVariant::Tutte, ParameterizeVariant::Floater, ParameterizeVariant::Stretch,
              ParameterizeVariant::Density, ParameterizeVariant::Uniform3d, ParameterizeVariant::Curvature}) {
            const passes::Parameterization map = passes::parameterize_square(nullptr, mesh, {.variant = variant});
            for (const auto& r : map.iterations)
                EXPECT_EQ(r.flipped, 0u) << name << " " << passes::variant_name(variant) << " iteration "
                                         << r.iteration;
            EXPECT_EQ(passes::count_flipped(mesh, map.uv), 0u) << name << " " << passes::variant_name(variant);
        }
    }
}

TEST_F(Parameterize, DensityEvensOutTheAreasMonotonically) {
    GIMG_REQUIRE_SHARED_MESH(path, "mushroom.off");
    const passes::Parameterization map =
        passes::parameterize_square(nullptr, geo::load_mesh(path), {.variant = ParameterizeVariant::Density});
    ASSERT_GE(map.iterations.size(), 6u);
    for (std::size_t t = 1; t < map.iterations.size(); ++t)
        EXPECT_LT(map.iterations[t].area_spread, map.iterations[t - 1].area_spread) << "iteration " << t;
    for (std::size_t t = 2; t < map.iterations.size(); ++t)
        EXPECT_LT(map.iterations[t].sigma_error, map.iterations[t - 1].sigma_error) << "iteration " << t;
    // sigma -> 1: E_sigma falls by more than an order of magnitude, the spread by more than 5 times.
    EXPECT_LT(map.iterations.back().sigma_error, map.iterations[1].sigma_error / 10.0);
    EXPECT_LT(map.iterations.back().area_spread, map.iterations[0].area_spread / 5.0);
}

TEST_F(Parameterize, StretchReweightingLowersTheL2Stretch) {
    const geo::Mesh mesh = bent_grid(24);
    const auto map = passes::parameterize_square(nullptr, mesh, {.variant = ParameterizeVariant::Stretch});
    ASSERT_GE(map.iterations.size(), 2u);
    EXPECT_LT(map.iterations[1].l2_stretch, map.iterations[0].l2_stretch);
    EXPECT_GT(map.iterations[0].l2_stretch, 1.0);  // the Floater start stretches this surface
}

TEST(ParameterizeFolds, AFoldedIterateEndsTheRunInsteadOfBreakingTheReweighting) {
    // Solved so loosely that Floater's map of a wavy 32 x 32 grid folds: its negative areas leave the
    // density reweighting no weights ("a matrix entry is not finite" before the run stopped there).
    geo::Mesh wavy = geo::make_grid(32, 32);
    for (auto& p : wavy.positions) p.z = 0.3 * std::sin(6.0 * p.x) * std::cos(5.0 * p.y);
    passes::ParameterizeOptions loose;
    loose.variant = passes::ParameterizeVariant::Density;
    loose.solve_tolerance = loose.iterate_tolerance = loose.fold_tolerance = 0.5;
    const passes::Parameterization map = passes::parameterize_square(nullptr, wavy, loose);
    ASSERT_EQ(map.iterations.size(), 1u);
    EXPECT_GT(map.iterations[0].flipped, 0u);
    // Solved on to the default fold tolerance when it folds, it does not, and the run goes on.
    loose.fold_tolerance = passes::ParameterizeOptions{}.fold_tolerance;
    const passes::Parameterization rescued = passes::parameterize_square(nullptr, wavy, loose);
    EXPECT_GT(rescued.iterations.size(), 1u);
    EXPECT_EQ(rescued.iterations[0].flipped, 0u);
    // Solved as by default, it folds nowhere and the run goes on.
    passes::ParameterizeOptions tight;
    tight.variant = passes::ParameterizeVariant::Density;
    const passes::Parameterization good = passes::parameterize_square(nullptr, wavy, tight);
    EXPECT_GT(good.iterations.size(), 2u);
    for (const auto& r : good.iterations) EXPECT_EQ(r.flipped, 0u) << r.iteration;
}

TEST(ParameterizeCurvature, FlatIsOneAndABumpStandsOut) {
    const geo::Mesh flat = geo::make_grid(10, 10);
    for (double c : passes::curvature_feature(flat, geo::build_adjacency(flat))) EXPECT_EQ(c, 1.0);
    geo::Mesh bump = geo::make_grid(30, 30);
    for (auto& p : bump.positions)
        p.z = 0.2 * std::exp(-40.0 * ((p.x - 0.5) * (p.x - 0.5) + (p.y - 0.5) * (p.y - 0.5)));
    const std::vector<double> c = passes::curvature_feature(bump, geo::build_adjacency(bump));
    const std::size_t top = 15 * 31 + 15, corner_region = 3 * 31 + 3;
    EXPECT_GT(c[top], 3.0 * c[corner_region]);
}

TEST_F(Parameterize, TheImageGridPutsItsBorderOnTheBoundary) {
    const geo::Mesh grid = jittered_grid(9);
    const passes::Parameterization map =
        passes::parameterize_square(nullptr, grid, {.variant = ParameterizeVariant::Floater});
    const std::uint32_t n = 33;
    const passes::PositionImage gpu = passes::geometry_image_gpu(ctx(), grid, map.uv, n);
    const passes::PositionImage cpu = passes::geometry_image_cpu(grid, map.uv, n);
    // The map is the identity, so pixel (a, b) holds (a / (N - 1), 1 - b / (N - 1), 0), up to the
    // border inset of 1/64 pixel.
    const double inset = (1.0 / 64.0) / (n - 1);
    for (const auto* image : {&gpu, &cpu})
        for (std::uint32_t b = 0; b < n; ++b)
            for (std::uint32_t a = 0; a < n; ++a) {
                const std::size_t o = image->index(a, b);
                ASSERT_TRUE(image->covered[o]) << a << "," << b << (image == &gpu ? " gpu" : " cpu");
                EXPECT_NEAR(image->xyz[3 * o], a / double(n - 1), inset + 1e-6);
                EXPECT_NEAR(image->xyz[3 * o + 1], 1.0 - b / double(n - 1), inset + 1e-6);
                EXPECT_NEAR(gpu.xyz[3 * o], cpu.xyz[3 * o], 1e-6);
                EXPECT_NEAR(gpu.xyz[3 * o + 1], cpu.xyz[3 * o + 1], 1e-6);
            }
    // The corners are the mesh's corners, within the inset.
    EXPECT_NEAR(gpu.xyz[3 * gpu.index(0, n - 1)], 0.0, inset + 1e-6);
    EXPECT_NEAR(gpu.xyz[3 * gpu.index(n - 1, 0)], 1.0, inset + 1e-6);
}

TEST(ParameterizeSelect, ReturnsTheIterateWhoseImageRebuildsTheMeshBest) {
    // Every iterate solved to full accuracy and kept, so the returned map is the chosen iterate itself.
    const geo::Mesh mesh = bent_grid(12);
    passes::ParameterizeOptions o{.variant = ParameterizeVariant::Curvature, .keep_iterates = true};
    o.select_size = 9;
    o.select_samples = 20'000;
    const passes::Parameterization map = passes::parameterize_square(nullptr, mesh, o);
    ASSERT_GE(map.iterations.size(), 3u);
    ASSERT_EQ(map.iterates.size(), map.iterations.size());
    std::size_t least = 0;
    for (std::size_t t = 0; t < map.iterations.size(); ++t) {
        EXPECT_GT(map.iterations[t].image_rms, 0.0) << "iteration " << t;
        if (map.iterations[t].image_rms < map.iterations[least].image_rms) least = t;
    }
    EXPECT_EQ(map.selected, least);
    EXPECT_EQ(map.uv, map.iterates[least]);
    EXPECT_EQ(passes::geometry_image_rms(mesh, map.uv, 9, 20'000), map.iterations[least].image_rms);
    // Without select_size the last iterate comes back, and nothing is measured.
    o.select_size = 0;
    const passes::Parameterization last = passes::parameterize_square(nullptr, mesh, o);
    EXPECT_EQ(last.selected, last.iterations.size() - 1);
    EXPECT_EQ(last.uv, last.iterates.back());
    EXPECT_EQ(last.iterations.back().image_rms, 0.0);
}

TEST(ParameterizeSelect, KeepsTheCurvatureMapOfANearlyFlatTerrainAboveFloaters) {
    // Run to its stopping rule, the curvature reweighting draws terrain's samples into its one ridge
    // and leaves the flat rest and the corners sparse: at N = 43 it ends 8 dB below Floater's start.
    // Its early iterates are better than that start; --select returns one of them.
    GIMG_REQUIRE_SHARED_MESH(path, "terrain.obj");
    const geo::Mesh mesh = geo::load_mesh(path);
    const std::uint32_t n = 43;
    const std::size_t samples = 100'000;
    auto psnr = [&](const std::vector<glm::dvec2>& uv) {
        return -20.0 * std::log10(passes::geometry_image_rms(mesh, uv, n, samples));
    };
    const double floater =
        psnr(passes::parameterize_square(nullptr, mesh, {.variant = ParameterizeVariant::Floater}).uv);
    const double last =
        psnr(passes::parameterize_square(nullptr, mesh, {.variant = ParameterizeVariant::Curvature}).uv);
    passes::ParameterizeOptions o{.variant = ParameterizeVariant::Curvature};
    o.select_size = n;
    const passes::Parameterization selected = passes::parameterize_square(nullptr, mesh, o);
    EXPECT_LT(last, floater - 3.0);
    EXPECT_GT(psnr(selected.uv), floater + 1.0);
    EXPECT_GT(selected.selected, 0u);
    EXPECT_LT(selected.selected, selected.iterations.size() - 1);
}

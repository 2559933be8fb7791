// Surfaces cut open for the square map (cut_to_disk): a sphere, a torus and an annulus become disks
// whose maps turn no triangle and whose geometry images keep the shape; the paths lower the
// stretch they are chosen by; the GPU's maps choose the cut the CPU twin's do.
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/topology.h"
#include "gimg/passes/parameterize.h"
#include "gimg/passes/reconstruct.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

using namespace gimg;

namespace {

class DiskCutMap : public gimg::test::GpuTest {};

geo::Mesh annulus() {
    geo::Mesh m = geo::make_grid(7, 7);  // without its middle cell
    std::erase_if(m.triangles, [&](const glm::uvec3& t) {
        const glm::dvec3 c = (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0;
        return std::abs(c.x - 0.5) < 0.07 && std::abs(c.y - 0.5) < 0.07;
    });
    m.texcoords.clear();
    return m;
}

// The cut is a disk the square map takes, its map turns nothing, and the stretch series is what
// `paths` says: the kept cut's map is the first of the least stretch.
void expect_usable_cut(const geo::Mesh& mesh, const passes::DiskCut& cut, const char* what) {
    EXPECT_NO_THROW(passes::check_disk_mesh(cut.disk)) << what;
    EXPECT_EQ(cut.disk.face_count(), mesh.face_count() + 2 * cut.split_edges) << what;
    ASSERT_EQ(cut.source.size(), cut.disk.vertex_count()) << what;
    for (std::size_t v = 0; v < cut.source.size(); ++v)
        if (cut.source[v] != geo::kInvalidIndex) {
            EXPECT_EQ(cut.disk.positions[v], mesh.positions[cut.source[v]]);
        }
    ASSERT_LT(cut.paths, cut.l2_stretch.size()) << what;
    for (std::size_t k = 0; k < cut.l2_stretch.size(); ++k)
        if (k != cut.paths) {
            EXPECT_GE(cut.l2_stretch[k], 0.99 * cut.l2_stretch[cut.paths]) << what << " path " << k;
        }
    const passes::Parameterization map = passes::parameterize_square(nullptr, cut.disk);
    for (const auto& r : map.iterations) EXPECT_EQ(r.flipped, 0u) << what << " iteration " << r.iteration;
    // No face left flat on a side of the square, where no pixel would sample it.
    std::size_t flat = 0;
    for (const glm::uvec3& t : cut.disk.triangles) {
        const glm::dvec2 a = map.uv[t.x], b = map.uv[t.y], c = map.uv[t.z];
        flat += !((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) > 0.0);
    }
    EXPECT_EQ(flat, 0u) << what;
}

}  // namespace

TEST_F(DiskCutMap, ASphereOpensIntoADiskWhoseImageKeepsTheSphere) {
    const geo::Mesh sphere = geo::make_icosphere(1.0, 3);
    const passes::DiskCut gpu = passes::cut_to_disk(&ctx(), sphere);
    const passes::DiskCut cpu = passes::cut_to_disk(nullptr, sphere);
    expect_usable_cut(sphere, cpu, "sphere");
    // The GPU's Floater maps agree with the CPU twin's to the solver's tolerance: the same cut.
    EXPECT_EQ(gpu.cut_edges, cpu.cut_edges);
    EXPECT_EQ(gpu.paths, cpu.paths);
    ASSERT_EQ(gpu.l2_stretch.size(), cpu.l2_stretch.size());
    for (std::size_t k = 0; k < cpu.l2_stretch.size(); ++k)
        EXPECT_NEAR(gpu.l2_stretch[k], cpu.l2_stretch[k], 1e-6 * cpu.l2_stretch[k]);
    EXPECT_EQ(gpu.disk.triangles, cpu.disk.triangles);
    // Its 33 x 33 image rebuilds the sphere: the seam's two sides sampled, no region crushed away.
    const passes::Parameterization map = passes::parameterize_square(nullptr, cpu.disk);
    EXPECT_EQ(passes::count_flipped(cpu.disk, map.uv), 0u);
    EXPECT_LT(passes::geometry_image_rms(cpu.disk, map.uv, 33, 20'000), 2e-3);  // 8.6e-4 when written
}

TEST(DiskCutMapCpu, ATorusAndAnAnnulusOpenIntoDisks) {
    const geo::Mesh torus = geo::make_torus(2.0, 0.6, 32, 12);
    expect_usable_cut(torus, passes::cut_to_disk(nullptr, torus), "torus");
    const geo::Mesh ring = annulus();
    ASSERT_EQ(geo::analyze_topology(ring).boundary_loops, 2u);
    expect_usable_cut(ring, passes::cut_to_disk(nullptr, ring), "annulus");
}

// The image of a cut surface on seam_boundary: each border pixel's mate samples the same point (to
// the sampler's 1/64-pixel inset), and joined, the reconstruction is closed with the input's genus
// and holes. Returns the RMS distance between mates before joining over the RMS distance to the
// pixel after the mate (what a table off by one would give).
double expect_closed_over_the_seam(Context* ctx, const geo::Mesh& mesh, std::uint32_t size, const char* what) {
    passes::DiskCut cut = passes::cut_to_disk(ctx, mesh);
    const auto seam = passes::seam_boundary(cut, size);
    EXPECT_TRUE(seam.has_value()) << what;
    if (!seam) return 0.0;
    EXPECT_EQ(seam->mate.size(), 4u * (size - 1)) << what;
    for (std::uint32_t s : seam->mate) EXPECT_LT(s, seam->mate.size()) << what;
    passes::ParameterizeOptions options;
    options.boundary = seam->boundary;
    const passes::Parameterization map = passes::parameterize_square(ctx, cut.disk, options);
    EXPECT_EQ(passes::count_flipped(cut.disk, map.uv), 0u) << what;
    passes::PositionImage image = ctx ? passes::geometry_image_gpu(*ctx, cut.disk, map.uv, size)
                                      : passes::geometry_image_cpu(cut.disk, map.uv, size);
    auto at = [&](std::uint32_t s) {
        const glm::uvec2 p = passes::border_pixel(s % std::uint32_t(seam->mate.size()), size);
        const std::size_t i = image.index(p.x, p.y);
        return glm::dvec3(image.xyz[3 * i], image.xyz[3 * i + 1], image.xyz[3 * i + 2]);
    };
    double apart = 0.0, off = 0.0;
    for (std::uint32_t s = 0; s < seam->mate.size(); ++s) {
        apart += std::pow(glm::distance(at(s), at(seam->mate[s])), 2.0);
        off += std::pow(glm::distance(at(s), at(seam->mate[s] + 1)), 2.0);
    }
    EXPECT_GT(passes::join_seam(image, seam->mate), 0u) << what;
    for (std::uint32_t s = 0; s < seam->mate.size(); ++s) EXPECT_EQ(at(s), at(seam->mate[s])) << what;
    geo::Mesh back = passes::reconstruct_cpu(image);
    passes::close_seam(back);
    const geo::MeshInfo in = geo::analyze_topology(mesh), out = geo::analyze_topology(back);
    EXPECT_EQ(out.components, 1u) << what;
    EXPECT_TRUE(out.manifold) << what;
    EXPECT_TRUE(out.oriented) << what;
    EXPECT_EQ(out.boundary_loops, in.boundary_loops) << what;
    EXPECT_EQ(out.component_info.at(0).genus, in.component_info.at(0).genus) << what;
    return std::sqrt(apart / off);
}

// Mates 0.013-0.062 of a step apart when written (the inset); a table off by one step gives about 1.
TEST_F(DiskCutMap, ASphereTorusAndAnnulusCloseOverTheSeam) {
    EXPECT_LT(expect_closed_over_the_seam(&ctx(), geo::make_icosphere(1.0, 3), 33, "sphere"), 0.1);
    EXPECT_LT(expect_closed_over_the_seam(nullptr, geo::make_icosphere(1.0, 3), 33, "sphere (CPU)"), 0.1);
    EXPECT_LT(expect_closed_over_the_seam(nullptr, geo::make_torus(2.0, 0.6, 32, 12), 41, "torus"), 0.1);
    EXPECT_LT(expect_closed_over_the_seam(nullptr, annulus(), 17, "annulus"), 0.1);
}

// A hole of one cell in a 16 x 16 grid, and a torus whose tube is a tenth of its ring: at 12 x 12 the
// hole's rim and the tube's loop are too short for more than a step or two of the perimeter by length,
// and joined, such a loop closed to a point or an edge. Four steps each keep them open.
TEST(DiskCutMapCpu, SmallHolesAndHandlesStayOpenInSmallImages) {
    geo::Mesh grid = geo::make_grid(16, 16);
    std::erase_if(grid.triangles, [&](const glm::uvec3& t) {
        const glm::dvec3 c = (grid.positions[t.x] + grid.positions[t.y] + grid.positions[t.z]) / 3.0;
        return std::abs(c.x - 0.53) < 0.03 && std::abs(c.y - 0.53) < 0.03;
    });
    grid.texcoords.clear();
    ASSERT_EQ(geo::analyze_topology(grid).boundary_loops, 2u);
    expect_closed_over_the_seam(nullptr, grid, 12, "a one-cell hole");
    expect_closed_over_the_seam(nullptr, geo::make_torus(2.0, 0.2, 48, 6), 12, "a thin torus");
}

// The smallest tori: every loop of their cuts a few edges long. At 5 x 5 their loops' 5 and 3 steps
// do not fit the 16 of the perimeter and the seam stays open; from 6 x 6 on they close, a torus each
// (with at least 4 and 2 steps the 4 x 3 torus pinched up to 9 x 9, where a corner of the square fell
// inside two short paths between the same nodes).
TEST_F(DiskCutMap, TheSmallestToriCloseOverTheSeamAtEverySize) {
    for (Context* c : {&ctx(), static_cast<Context*>(nullptr)})
        for (int ring : {3, 4}) {
            geo::Mesh torus = geo::make_torus(2.0, 0.6, ring, 3);
            for (glm::dvec3& p : torus.positions) p = glm::dvec3(glm::vec3(p));  // as read from a file
            const std::string what =
                "a torus of " + std::to_string(ring) + " x 3 vertices (" + (c ? "GPU" : "CPU") + ")";
            passes::DiskCut cut = passes::cut_to_disk(c, torus);
            EXPECT_FALSE(passes::seam_boundary(cut, 5).has_value()) << what;
            for (std::uint32_t size = 6; size <= 12; ++size)
                expect_closed_over_the_seam(c, torus, size, (what + " at " + std::to_string(size)).c_str());
        }
}

TEST(DiskCutMapCpu, TheCamelClosesOverItsSeam) {
    GIMG_REQUIRE_SHARED_MESH(path, "camel.off");
    EXPECT_LT(expect_closed_over_the_seam(nullptr, geo::load_mesh(path), 99, "camel"), 0.1);
}

TEST(DiskCutMapCpu, PathsFreeTheCamelsLegs) {
    GIMG_REQUIRE_SHARED_MESH(path, "camel.off");
    const geo::Mesh camel = geo::load_mesh(path);
    const passes::DiskCut cut = passes::cut_to_disk(nullptr, camel);
    expect_usable_cut(camel, cut, "camel");
    // A seam from one far point to another leaves the other legs crushed; paths out to them undo it.
    EXPECT_GE(cut.paths, 2u);
    EXPECT_LT(cut.l2_stretch[cut.paths], 1e-3 * cut.l2_stretch.front());
}

// Where the two initial cut graphs differ both are mapped, and the cut kept is the one whose Floater
// map has the lower stretch; a sphere's are the same seam.
TEST(DiskCutMapCpu, TheInitialCutKeptHasTheLowerStretch) {
    const geo::Mesh torus = geo::make_torus(2.0, 0.6, 32, 12);
    const passes::DiskCut cut = passes::cut_to_disk(nullptr, torus);
    expect_usable_cut(torus, cut, "torus");
    ASSERT_EQ(cut.graph_l2_stretch.size(), 2u);
    const bool loops = cut.graph == geo::CutGraph::ShortestLoops;
    EXPECT_EQ(cut.graph_l2_stretch[loops], cut.l2_stretch[cut.paths]);
    EXPECT_LE(cut.graph_l2_stretch[loops], cut.graph_l2_stretch[!loops]);
    EXPECT_GT(cut.tried, cut.l2_stretch.size());
    const passes::DiskCut sphere = passes::cut_to_disk(nullptr, geo::make_icosphere(1.0, 2));
    EXPECT_TRUE(sphere.graph_l2_stretch.empty());
    EXPECT_EQ(sphere.tried, sphere.l2_stretch.size());
}

// With select_size, a mesh with two cut graphs is mapped with both and the map kept is the one whose
// selected iterate's image rebuilds it better; without, the lower stretch decides alone.
TEST(DiskCutMapCpu, SelectingMapsBothCutGraphsAndKeepsTheBetterImage) {
    const geo::Mesh torus = geo::make_torus(2.0, 0.6, 32, 12);
    passes::ParameterizeOptions options;
    options.select_size = 21;
    options.select_samples = 5'000;
    const passes::CutMap both = passes::cut_and_map(nullptr, torus, 21, options);
    ASSERT_EQ(both.graph_image_rms.size(), 2u);
    const bool loops = both.cut.graph == geo::CutGraph::ShortestLoops;
    EXPECT_EQ(both.graph_image_rms[loops], both.map.iterations[both.map.selected].image_rms);
    EXPECT_LE(both.graph_image_rms[loops], both.graph_image_rms[!loops]);
    ASSERT_TRUE(both.seam.has_value());
    EXPECT_EQ(both.seam->boundary.loop.size(),
              passes::square_boundary(both.cut.disk, geo::build_adjacency(both.cut.disk)).loop.size());
    // Each graph alone gives its own figure.
    for (geo::CutGraph g : {geo::CutGraph::FaceTree, geo::CutGraph::ShortestLoops}) {
        const passes::CutMap one = passes::cut_and_map(nullptr, torus, 21, options, {.graph = g});
        EXPECT_TRUE(one.graph_image_rms.empty());
        EXPECT_EQ(one.map.iterations[one.map.selected].image_rms,
                  both.graph_image_rms[g == geo::CutGraph::ShortestLoops]);
    }
    options.select_size = 0;
    EXPECT_TRUE(passes::cut_and_map(nullptr, torus, 21, options).graph_image_rms.empty());
}

// holes (7 boundary loops): the face tree's paths ran along the rims and one another, and the strips
// between them were crushed until 6 triangles turned over in every cut tried; zipped, or with the
// shortest loops, none does.
TEST(DiskCutMapCpu, HolesOpensIntoADiskWithoutCrushedStrips) {
    GIMG_REQUIRE_SHARED_MESH(path, "holes.off");
    const geo::Mesh holes = geo::load_mesh(path);
    expect_usable_cut(holes, passes::cut_to_disk(nullptr, holes), "holes");
}

// Three border pixels around a corner of a 6 x 6 image joined into one vertex (two one-step leaves
// of a cut node, as on a part of the retrieval collection's dog): the corner's inner pixel touches all
// three, and closed over the seam the mesh has an edge of more than two faces. rebuild_over_seam
// then leaves the image and the mesh open; a seam that closes well it joins.
TEST(DiskCutMapCpu, ASeamThatWouldPinchStaysOpen) {
    const std::uint32_t n = 6, steps = 4 * (n - 1);
    passes::PositionImage image(n, n);
    for (std::uint32_t b = 0; b < n; ++b)
        for (std::uint32_t a = 0; a < n; ++a) {
            const std::size_t i = image.index(a, b);
            image.xyz[3 * i] = float(a), image.xyz[3 * i + 1] = float(b);
            image.xyz[3 * i + 2] = float(0.1 * std::sin(1.7 * a + 2.3 * b));
            image.covered[i] = 1;
        }
    passes::SeamBoundary seam;
    seam.mate.resize(steps);
    for (std::uint32_t s = 0; s < steps; ++s) seam.mate[s] = s;
    // Step 0 is the corner (0, n - 1); steps - 2 and 2 lie two pixels up and two to the right: one
    // vertex near the corner, the leaves' tips between its copies close to each other, so that the
    // corner's quad is split between the tips and the quads beside it through the vertex.
    ASSERT_EQ(passes::border_pixel(0, n), glm::uvec2(0, n - 1));
    seam.mate[steps - 2] = 0, seam.mate[0] = 2, seam.mate[2] = steps - 2;
    const float y = float(n - 1);
    auto place = [&](std::uint32_t a, std::uint32_t b, glm::vec3 p) {
        const std::size_t i = image.index(a, b);
        image.xyz[3 * i] = p.x, image.xyz[3 * i + 1] = p.y, image.xyz[3 * i + 2] = p.z;
    };
    for (std::uint32_t s : {steps - 2, 0u, 2u})
        place(passes::border_pixel(s, n).x, passes::border_pixel(s, n).y, {0.2f, y - 0.8f, 0.0f});
    place(0, n - 2, {0.1f, y - 0.6f, 0.0f});
    place(1, n - 1, {0.3f, y - 0.5f, 0.0f});
    const passes::PositionImage before = image;

    passes::PositionImage joined = image;
    passes::join_seam(joined, seam.mate);
    geo::Mesh pinched = passes::reconstruct_cpu(joined);
    passes::close_seam(pinched);
    EXPECT_GT(geo::analyze_topology(pinched).non_manifold_edges, 0u);

    const passes::SeamJoin open = passes::rebuild_over_seam(
        image, seam, [](const passes::PositionImage& im) { return passes::reconstruct_cpu(im); });
    EXPECT_FALSE(open.joined);
    EXPECT_EQ(image.xyz, before.xyz);
    const geo::MeshInfo info = geo::analyze_topology(open.mesh);
    EXPECT_EQ(info.non_manifold_edges + info.non_manifold_vertices, 0u);
    EXPECT_EQ(open.mesh.face_count(), passes::reconstruct_cpu(before).face_count());

    // A torus's seam closes: joined, one closed manifold piece of genus 1.
    const geo::Mesh torus = geo::make_torus(2.0, 0.6, 32, 12);
    const passes::CutMap cut = passes::cut_and_map(nullptr, torus, 21, {});
    passes::PositionImage torus_image = passes::geometry_image_cpu(cut.cut.disk, cut.map.uv, 21);
    const passes::SeamJoin closed = passes::rebuild_over_seam(
        torus_image, cut.seam, [](const passes::PositionImage& im) { return passes::reconstruct_cpu(im); });
    EXPECT_TRUE(closed.joined);
    EXPECT_GT(closed.merged_vertices, 0u);
    const geo::MeshInfo torus_info = geo::analyze_topology(closed.mesh);
    EXPECT_TRUE(torus_info.closed);
    ASSERT_EQ(torus_info.component_info.size(), 1u);
    EXPECT_EQ(torus_info.component_info[0].genus, 1);
}

// femur (genus 2) cut along its shortest loops: the curvature run's E_sigma rises from the fourth
// iteration on while the reweighting opens the parts the cut crushed. The thesis's rule stops at
// that rise; cut_and_map runs on through it, and its image rebuilds the femur several times better.
TEST(DiskCutMapCpu, ARiseOfESigmaDoesNotEndTheRunOnACutSurface) {
    GIMG_REQUIRE_SHARED_MESH(path, "femur.off");
    const geo::Mesh femur = geo::load_mesh(path);
    const std::uint32_t size = 62;  // round(sqrt(vertices))
    passes::ParameterizeOptions options;
    const passes::CutMap cut = passes::cut_and_map(nullptr, femur, size, options);
    const std::vector<passes::IterationReport>& runs = cut.map.iterations;
    std::size_t rise = 0;
    for (std::size_t t = 2; t < runs.size() && rise == 0; ++t)
        if (runs[t].sigma_error > runs[t - 1].sigma_error) rise = t;
    ASSERT_GT(rise, 0u);
    EXPECT_GT(cut.map.selected, rise + 2);
    EXPECT_EQ(passes::count_flipped(cut.cut.disk, cut.map.uv), 0u);

    ASSERT_TRUE(cut.seam.has_value());
    options.boundary = cut.seam->boundary;
    const passes::Parameterization stopped = passes::parameterize_square(nullptr, cut.cut.disk, options);
    EXPECT_EQ(stopped.selected, rise);
    const double on = passes::geometry_image_rms(cut.cut.disk, cut.map.uv, size, 20'000);
    const double at_rise = passes::geometry_image_rms(cut.cut.disk, stopped.uv, size, 20'000);
    EXPECT_LT(on, 0.3 * at_rise) << "on through the rise " << on << ", stopped at it " << at_rise;
}

// tests/data/real/table_piece.ply cut along its face tree: at 16 x 16 one iterate of its curvature
// map folds a triangle and rebuilds the piece better than every iterate that does not. select
// returns the best of those that do not.
TEST(DiskCutMapCpu, SelectNeverReturnsAFoldedIterate) {
    const geo::Mesh part = geo::load_mesh(std::filesystem::path(GIMG_TEST_DATA_DIR) / "real" / "table_piece.ply");
    passes::ParameterizeOptions options;
    options.select_size = 16;
    const passes::CutMap cut = passes::cut_and_map(nullptr, part, 16, options, {.graph = geo::CutGraph::FaceTree});
    const std::vector<passes::IterationReport>& runs = cut.map.iterations;
    double folded = std::numeric_limits<double>::infinity();
    for (const passes::IterationReport& r : runs)
        if (r.flipped > 0) folded = std::min(folded, r.image_rms);
    const passes::IterationReport& chosen = runs[cut.map.selected];
    ASSERT_LT(folded, chosen.image_rms) << "the case this test is for: a folded iterate rebuilds better";
    EXPECT_EQ(chosen.flipped, 0u);
    EXPECT_EQ(passes::count_flipped(cut.cut.disk, cut.map.uv), 0u);
    for (const passes::IterationReport& r : runs)
        if (r.flipped == 0) {
            EXPECT_GE(r.image_rms, chosen.image_rms);
        }
}

// A reweighted iterate whose solve fails ends the run, as a fold does, and the earlier iterates
// stand. Forced here by a cap of 10 solver iterations a solve: table_piece's iterates 0-9 need at
// most 10 a solve, its iterate 10 more.
TEST(DiskCutMapCpu, AnIterateThatCannotBeSolvedEndsTheRun) {
    const geo::Mesh part = geo::load_mesh(std::filesystem::path(GIMG_TEST_DATA_DIR) / "real" / "table_piece.ply");
    passes::ParameterizeOptions options;
    const passes::CutMap full = passes::cut_and_map(nullptr, part, 16, options, {.graph = geo::CutGraph::FaceTree});
    ASSERT_GT(full.map.iterations.size(), 11u);
    ASSERT_GT(full.map.iterations[10].solver_iterations, 10u);
    options.max_solver_iterations = 10;
    const passes::CutMap cut = passes::cut_and_map(nullptr, part, 16, options, {.graph = geo::CutGraph::FaceTree});
    EXPECT_NE(cut.map.unsolved.find("iteration 10: "), std::string::npos) << cut.map.unsolved;
    EXPECT_TRUE(full.map.unsolved.empty());
    ASSERT_EQ(cut.map.iterations.size(), 10u);  // iterates 0 to 9, as in the full run
    for (std::size_t t = 0; t < 10; ++t)
        EXPECT_EQ(cut.map.iterations[t].sigma_error, full.map.iterations[t].sigma_error);
    EXPECT_EQ(cut.map.selected, 9u);
    EXPECT_EQ(passes::count_flipped(cut.cut.disk, cut.map.uv), 0u);
}

// A sphere with one face missing is a disk whose boundary has 3 vertices, one fewer than the
// square's corners: its longest boundary edge is split for the first map (refused before), and
// the cut and the map are made.
TEST(DiskCutMapCpu, ATriangularHoleGetsAVertexForEachCorner) {
    geo::Mesh m = geo::make_icosphere(1.0, 2);
    m.triangles.erase(m.triangles.begin());
    const passes::CutMap cut = passes::cut_and_map(nullptr, m, 12, {});
    EXPECT_EQ(passes::count_flipped(cut.cut.disk, cut.map.uv), 0u);
    const geo::MeshInfo info = geo::analyze_topology(cut.cut.disk);
    EXPECT_EQ(info.boundary_loops, 1u);
    EXPECT_GE(info.boundary_edges, 4u);
}

// On a surface it cut, cut_and_map measures Floater's start against the iterate the rule returns
// and keeps the better: table_piece cut along its shortest loops rebuilds at 16 x 16 far worse once
// reweighted (parts crushed), along its face tree better.
TEST(DiskCutMapCpu, ACutSurfaceKeepsTheStartWhereReweightingRebuildsWorse) {
    const geo::Mesh part = geo::load_mesh(std::filesystem::path(GIMG_TEST_DATA_DIR) / "real" / "table_piece.ply");
    const passes::CutMap loops = passes::cut_and_map(nullptr, part, 16, {}, {.graph = geo::CutGraph::ShortestLoops});
    ASSERT_GT(loops.cut.cut_edges, 0u);
    EXPECT_EQ(loops.map.selected, 0u);
    const std::vector<passes::IterationReport>& runs = loops.map.iterations;
    ASSERT_GT(runs.size(), 2u);
    double rule = 0.0;  // the image RMS of the iterate the rule chose, measured against the start
    for (std::size_t t = 1; t < runs.size(); ++t) rule = std::max(rule, runs[t].image_rms);
    EXPECT_GT(rule, 2.0 * runs[0].image_rms) << "the reweighted map crushes parts of this piece";
    EXPECT_NEAR(passes::geometry_image_rms(loops.cut.disk, loops.map.uv, 16, 50'000), runs[0].image_rms,
                0.1 * runs[0].image_rms);

    const passes::CutMap tree = passes::cut_and_map(nullptr, part, 16, {}, {.graph = geo::CutGraph::FaceTree});
    ASSERT_GT(tree.map.selected, 0u);
    EXPECT_LT(tree.map.iterations[tree.map.selected].image_rms, tree.map.iterations[0].image_rms);
}

// The third candidate: motorbike_piece's iterate of least E_sigma rebuilds it better at 13 x 13
// than the start and the iterate the rule returns, and is returned.
TEST(DiskCutMapCpu, ACutSurfaceCanKeepTheIterateOfLeastSigma) {
    const geo::Mesh part = geo::load_mesh(std::filesystem::path(GIMG_TEST_DATA_DIR) / "real" / "motorbike_piece.ply");
    const passes::CutMap cut = passes::cut_and_map(nullptr, part, 13, {});
    ASSERT_GT(cut.cut.cut_edges, 0u);
    const std::vector<passes::IterationReport>& runs = cut.map.iterations;
    std::size_t least = 0, last = 0;  // the candidates besides the start
    for (std::size_t t = 1; t < runs.size(); ++t) {
        if (runs[t].flipped > 0) continue;
        last = t;
        if (least == 0 || runs[t].sigma_error < runs[least].sigma_error) least = t;
    }
    ASSERT_GT(least, 0u);
    ASSERT_GT(last, least);
    EXPECT_EQ(cut.map.selected, least);
    EXPECT_LT(runs[least].image_rms, 0.95 * runs[last].image_rms);
    EXPECT_LT(runs[least].image_rms, 0.95 * runs[0].image_rms);
}

TEST(DiskCutMapCpu, RefusesWhatNoCutMakesADisk) {
    auto refusal = [](const geo::Mesh& m) {
        try {
            passes::cut_to_disk(nullptr, m);
        } catch (const geo::InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    geo::Mesh two = geo::make_icosphere(1.0, 1);
    const geo::Mesh other = geo::make_icosphere(1.0, 1, {3, 0, 0});
    const auto offset = std::uint32_t(two.positions.size());
    for (auto p : other.positions) two.positions.push_back(p);
    for (auto t : other.triangles) two.triangles.push_back(t + offset);
    EXPECT_NE(refusal(two).find("2 components"), std::string::npos) << refusal(two);
    geo::Mesh fin = geo::make_icosphere(1.0, 1);  // a third face on one edge
    const glm::uvec3 t = fin.triangles[0];
    fin.positions.push_back({2, 2, 2});
    fin.triangles.push_back({t.x, t.y, std::uint32_t(fin.positions.size() - 1)});
    EXPECT_NE(refusal(fin).find("non-manifold"), std::string::npos) << refusal(fin);
}

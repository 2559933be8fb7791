// Hierarchical cylindrical ray casting (the thesis, chapter 3): every decoded sample lies on the
// surface it was cast at, level 1 is the ordinary image, and the hierarchy reaches what one
// projection cannot see.
#include "cylinder_cases.h"
#include "gpu_test.h"
#include "test_data.h"

#include "gimg/geometry/bvh.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/io.h"
#include "gimg/geometry/shapes.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/passes/cylinder_hierarchy.h"
#include "gimg/passes/reconstruct.h"

#include <gtest/gtest.h>

#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <limits>

using namespace gimg;
namespace gp = gimg::passes;

namespace {

// The largest distance of a level's valid samples from the mesh (in the cylinder frame), and
// how many there are.
std::pair<double, std::size_t> off_surface(const gp::CylinderMesh& mesh, const gp::HierarchyGrid& grid) {
    const geo::TriangleBvh bvh(gp::to_cylinder_frame(mesh));
    double worst = 0.0;
    std::size_t valid = 0;
    for (std::size_t i = 0; i < grid.points.size(); ++i) {
        if (grid.valid[i] != gp::kHierarchyHit) continue;
        ++valid;
        worst = std::max(worst, bvh.closest_point(grid.points[i]).distance);
    }
    return {worst, valid};
}

}  // namespace

TEST(CylinderHierarchy, SamplesOfASphereLieOnItAtEveryLevel) {
    const geo::Mesh sphere = geo::make_icosphere(0.4, 4);
    const gp::CylinderMesh mesh = gp::make_cylinder_mesh(sphere, gp::fit_cylinder_frame(sphere));
    // Without a reach limit (the thesis) every ray of a sphere finds it.
    const gp::CylinderHierarchy h = gp::cylinder_hierarchy_cpu(mesh, {.base = 16, .size = 128, .reach = 0.0});
    ASSERT_EQ(h.levels(), 4u);
    for (std::uint32_t level = 1; level <= 4; ++level) {
        const gp::HierarchyGrid grid = gp::decode_cylinder_hierarchy(h, level);
        ASSERT_EQ(grid.side, 16u << (level - 1));
        const auto [worst, valid] = off_surface(mesh, grid);
        EXPECT_LT(worst, 1e-6) << "level " << level;
        // Every row but the last of each level's new samples sees the sphere.
        EXPECT_GT(valid, std::size_t(0.9 * grid.side * grid.side)) << "level " << level;
    }
}

TEST(CylinderHierarchy, LevelOneIsTheOrdinaryImage) {
    // The scanline method (the thesis's ch. 4 algorithm, not the ray caster the encoder uses).
    const geo::Mesh torus = geo::make_torus(0.3, 0.12, 48, 24);
    const gp::CylinderMesh mesh = gp::make_cylinder_mesh(torus, gp::fit_cylinder_frame(torus));
    const gp::CylinderHierarchy h = gp::cylinder_hierarchy_cpu(mesh, {.base = 32, .size = 64});
    const gp::CylinderImage ordinary = gp::cylinder_scanline(mesh, 32, 32);
    const gp::HierarchyGrid level1 = gp::decode_cylinder_hierarchy(h, 1);
    const auto dirs = gp::cylinder_directions(32);
    std::size_t covered = 0;
    for (std::uint32_t v = 0; v < 32; ++v)
        for (std::uint32_t u = 0; u < 32; ++u) {
            const std::size_t i = ordinary.index(u, v);
            ASSERT_EQ(bool(level1.valid[i]), bool(ordinary.covered[i])) << u << "," << v;
            if (!ordinary.covered[i]) continue;
            ++covered;
            const double d = ordinary.distance[i], y = 1.0 - (v + 0.5) / 32.0;
            EXPECT_LT(glm::distance(level1.points[i], glm::dvec3(d * dirs[u][0], y, d * dirs[u][1])), 1e-6);
        }
    EXPECT_GT(covered, 200u);
}

TEST(CylinderHierarchy, ReachesBehindAPlateThatHidesTheBody) {
    // A sphere with a plate in front of it (seen from the +x wall): one projection sees the plate,
    // not the band of the sphere behind it. The hierarchy casts around the plate's edges and
    // samples that band; measured as the distance from the band's points to each reconstruction.
    geo::Mesh model = geo::make_icosphere(0.3, 4);
    const geo::Mesh plate = geo::make_box({0.04, 0.16, 0.5}, 4);
    const auto first = std::uint32_t(model.positions.size());
    for (const auto& p : plate.positions) model.positions.push_back(p + glm::dvec3(0.42, 0.0, 0.0));
    for (const auto& t : plate.triangles) model.triangles.push_back(t + glm::uvec3(first));
    model.normals.clear();
    const gp::CylinderFrame frame = gp::fit_cylinder_frame(model, false);
    const gp::CylinderMesh mesh = gp::make_cylinder_mesh(model, frame);

    const std::uint32_t n = 128;
    const geo::Mesh hierarchical = gp::hierarchy_mesh(
        gp::decode_cylinder_hierarchy(gp::cylinder_hierarchy_cpu(mesh, {.base = 32, .size = n}), 4 - 1), frame);
    gp::ReconstructOptions off;
    off.threshold = std::numeric_limits<float>::infinity();
    const geo::Mesh ordinary = gp::reconstruct_cpu(gp::cylinder_raycast(mesh, n / 2, n / 2), frame, off);
    // The hidden band: sphere points facing +x behind the plate.
    std::vector<glm::dvec3> band;
    for (std::size_t i = 0; i < first; ++i) {
        const glm::dvec3& p = model.positions[i];
        if (p.x > 0.2 && std::abs(p.y) < 0.05 && std::abs(p.z) < 0.15) band.push_back(p);
    }
    ASSERT_GT(band.size(), 20u);
    auto mean_distance = [&](const geo::Mesh& m) {
        const geo::TriangleBvh bvh(m);
        double sum = 0.0;
        for (const auto& p : band) sum += bvh.closest_point(p).distance;
        return sum / double(band.size());
    };
    const double d_hier = mean_distance(hierarchical), d_ord = mean_distance(ordinary);
    EXPECT_LT(d_hier, 0.5 * d_ord) << "hierarchical " << d_hier << ", ordinary " << d_ord;
}

TEST(CylinderHierarchy, FilesReadBackTheSameAndRefuseAnotherRunsImage) {
    const geo::Mesh torus = geo::make_torus(0.3, 0.12, 32, 16);
    const gp::CylinderFrame frame = gp::fit_cylinder_frame(torus);
    const gp::CylinderHierarchy h =
        gp::cylinder_hierarchy_cpu(gp::make_cylinder_mesh(torus, frame), {.base = 16, .size = 64});
    const auto dir = std::filesystem::path(GIMG_TEST_OUTPUT_DIR) / "hierarchy_files";
    std::filesystem::remove_all(dir);
    gp::write_hierarchy_files(dir, h, frame, {"torus", "hierarchical"});
    const gp::HierarchyFiles back = gp::read_hierarchy_files(dir / "hierarchy.exr");
    EXPECT_EQ(back.hierarchy.t, h.t);
    EXPECT_EQ(back.hierarchy.valid, h.valid);
    EXPECT_EQ(back.hierarchy.base, 16u);
    EXPECT_EQ(back.hierarchy.reach, h.reach);
    // Another run's image beside this frame.json.
    gp::CylinderHierarchy other = h;
    other.t[5] += 0.25f;
    other.valid[5] = gp::kHierarchyHit;
    gp::write_hierarchy_files(dir / "other", other, frame, {"torus", "hierarchical"});
    std::filesystem::copy_file(dir / "other" / "hierarchy.exr", dir / "hierarchy.exr",
                               std::filesystem::copy_options::overwrite_existing);
    EXPECT_THROW(gp::read_hierarchy_files(dir / "hierarchy.exr"), geo::InputError);
}

TEST(CylinderHierarchy, SizesThatAreNotBaseTimesAPowerOfTwoAreRefused) {
    const gp::CylinderMesh mesh = gimg::test::to_cylinder_mesh(geo::make_box({0.5, 0.5, 0.5}, 1));
    EXPECT_THROW(gp::cylinder_hierarchy_cpu(mesh, {.base = 32, .size = 96}), geo::InputError);
    EXPECT_THROW(gp::cylinder_hierarchy_cpu(mesh, {.base = 1, .size = 4}), geo::InputError);
    EXPECT_THROW(gp::cylinder_hierarchy_cpu(mesh, {.base = 16, .size = 64, .reach = -1.0}), geo::InputError);
}

TEST(CylinderHierarchy, RaysOfASphereLandNearTheirLaunchPoints) {
    // Every later ray of a sphere starts near it, inside (a chord's midpoint) and fires outwards:
    // a distance far beyond the sagitta means a ray went the wrong way and crossed the sphere.
    const geo::Mesh sphere = geo::make_icosphere(0.4, 5);
    const gp::CylinderMesh mesh = gp::make_cylinder_mesh(sphere, gp::fit_cylinder_frame(sphere));
    const gp::CylinderHierarchy h = gp::cylinder_hierarchy_cpu(mesh, {.base = 16, .size = 128, .reach = 0.0});
    double worst = 0.0;
    std::size_t positive = 0, later = 0;
    for (std::uint32_t v = 0; v < h.size; ++v)
        for (std::uint32_t u = 0; u < h.size; ++u) {
            if ((u < h.base && v < h.base) || h.valid[std::size_t(v) * h.size + u] != gp::kHierarchyHit) continue;
            const float t = h.t[std::size_t(v) * h.size + u];
            worst = std::max(worst, double(std::abs(t)));
            positive += t > 0.0f;
            ++later;
        }
    EXPECT_LT(worst, 0.05);
    EXPECT_GT(positive, later * 9 / 10) << "chord midpoints lie inside: most rays fire outwards";
}

namespace {
class CylinderHierarchyGpu : public gimg::test::GpuTest {};
}  // namespace

TEST_F(CylinderHierarchyGpu, TheGpuEncoderGivesTheCpuHierarchy) {
    std::vector<geo::Mesh> meshes{geo::make_torus(0.3, 0.12, 48, 24)};
    if (const auto path = gimg::test::shared_mesh("bunny.off")) meshes.push_back(geo::load_mesh(*path));
    for (const geo::Mesh& m : meshes) {
        const gp::CylinderMesh mesh = gp::make_cylinder_mesh(m, gp::fit_cylinder_frame(m));
        for (double reach : {2.0, 0.0}) {
            const gp::CylinderHierarchyOptions options{.base = 32, .size = 128, .reach = reach};
            const gp::CylinderHierarchy cpu = gp::cylinder_hierarchy_cpu(mesh, options);
            const gp::CylinderHierarchy gpu = gp::cylinder_hierarchy_gpu(ctx(), mesh, options);
            ASSERT_EQ(gpu.valid, cpu.valid);
            ASSERT_EQ(gpu.t, cpu.t);
            std::size_t hits = 0;
            for (auto v : cpu.valid) hits += v == gp::kHierarchyHit;
            EXPECT_GT(hits, 2000u);
            // Where the device times passes (lavapipe and GPUs do), the parity segments are a part
            // of the passes' time, as are the rays.
            if (gpu.gpu_ms > 0.0) {
                EXPECT_GT(gpu.gpu_parity_ms, 0.0);
                EXPECT_LT(gpu.gpu_parity_ms, gpu.gpu_ms);
            }
        }
    }
}

TEST_F(CylinderHierarchyGpu, DecodingOnTheGpuGivesTheCpuGrid) {
    std::vector<geo::Mesh> meshes{geo::make_torus(0.3, 0.12, 48, 24)};
    if (const auto path = gimg::test::shared_mesh("armadillo.off")) meshes.push_back(geo::load_mesh(*path));
    for (const geo::Mesh& m : meshes) {
        const gp::CylinderMesh mesh = gp::make_cylinder_mesh(m, gp::fit_cylinder_frame(m));
        const gp::CylinderHierarchy h = gp::cylinder_hierarchy_cpu(mesh, {.base = 16, .size = 128});
        for (std::uint32_t level = 1; level <= h.levels(); ++level) {
            const gp::HierarchyGrid cpu = gp::decode_cylinder_hierarchy(h, level);
            const gp::HierarchyGrid gpu = gp::decode_cylinder_hierarchy_gpu(ctx(), h, level);
            ASSERT_EQ(gpu.side, cpu.side);
            ASSERT_EQ(gpu.valid, cpu.valid) << "level " << level;
            ASSERT_EQ(gpu.outward, cpu.outward) << "level " << level;
            double worst = 0.0;
            for (std::size_t i = 0; i < cpu.points.size(); ++i)
                if (cpu.valid[i]) worst = std::max(worst, glm::distance(gpu.points[i], cpu.points[i]));
            EXPECT_LT(worst, 1e-9) << "level " << level;
        }
    }
}

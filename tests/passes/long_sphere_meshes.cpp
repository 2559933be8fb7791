// Long case (ctest label "long"): Kanai's method on every closed genus-0 shared mesh, with the
// table of metrics and times the GPU sphere solver is compared with. Prints the table and writes
// it to <build>/test-output/sphere/kanai_meshes.tsv.
#include "test_data.h"

#include "gimg/geometry/io.h"
#include "gimg/passes/sphere.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>

using namespace gimg;

TEST(SphereKanaiLong, EverySharedGenusZeroMesh) {
    if (!test::mesh_dir()) GTEST_SKIP() << "shared meshes not found (set GIMG_MESH_DIR)";
    std::ofstream tsv(test::output_dir("sphere") / "kanai_meshes.tsv");
    tsv << "mesh\tvertices\tfaces\tflips\tconformal_ratio\tangle_mean_deg\tangle_p95_deg\tangle_max_deg\t"
           "area_distortion\tqueue_pops\tseconds\n";
    std::printf("%-16s %7s %7s %5s %8s %7s %7s %7s %6s %10s %8s\n", "mesh", "V", "F", "flips", "ratio", "ang.mean",
                "ang.p95", "ang.max", "area", "pops", "seconds");
    for (const char* name : {"hand.off", "bunny_small.obj", "blobby.off", "triceratops.off", "cow.off", "dino.off",
                             "homer.off", "fandisk.off", "camel.off", "armadillo.off", "bunny.off"}) {
        auto path = test::shared_mesh(name);
        if (!path) {
            ADD_FAILURE() << "shared mesh " << name << " is missing";
            continue;
        }
        SCOPED_TRACE(name);
        const geo::Mesh mesh = geo::load_mesh(*path);
        const auto t0 = std::chrono::steady_clock::now();
        const passes::SphereResult r = passes::sphere_kanai(mesh);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const passes::SphereMetrics m = passes::sphere_metrics(mesh, r.positions);
        std::size_t pops = 0;
        for (const passes::SphereStage& s : r.stages)
            if (s.name.rfind("level", 0) == 0) pops += s.iterations;
        std::printf("%-16s %7zu %7zu %5zu %8.4f %7.2f %7.2f %7.2f %6.3f %10zu %8.2f\n", name, mesh.vertex_count(),
                    mesh.face_count(), m.flips, m.conformal_ratio, m.angle_distortion_deg.mean,
                    m.angle_distortion_deg.p95, m.angle_distortion_deg.max, m.area_distortion, pops, seconds);
        std::fflush(stdout);
        tsv << name << '\t' << mesh.vertex_count() << '\t' << mesh.face_count() << '\t' << m.flips << '\t'
            << m.conformal_ratio << '\t' << m.angle_distortion_deg.mean << '\t' << m.angle_distortion_deg.p95 << '\t'
            << m.angle_distortion_deg.max << '\t' << m.area_distortion << '\t' << pops << '\t' << seconds << '\n';
        EXPECT_TRUE(r.converged) << r.note;
        EXPECT_EQ(m.flips, 0u);
        EXPECT_LT(m.conformal_ratio, 1.15);
        EXPECT_GT(m.conformal_ratio, 0.98);
    }
}

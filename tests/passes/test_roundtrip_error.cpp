// Level of detail by image size: the roundtrip error (mesh -> cylindrical image -> mesh, against
// the original) falls as the image grows, on real meshes.
#include "test_data.h"

#include "gimg/geometry/io.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/passes/cylinder.h"
#include "gimg/passes/reconstruct.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace gimg;

class RoundtripError : public ::testing::TestWithParam<const char*> {};

TEST_P(RoundtripError, FallsMonotonicallyWithImageSize) {
    GIMG_REQUIRE_SHARED_MESH(path, GetParam());
    const geo::Mesh mesh = geo::load_mesh(path);
    const passes::CylinderFrame frame = passes::fit_cylinder_frame(mesh);
    const passes::CylinderMesh cyl = passes::make_cylinder_mesh(mesh, frame);
    geo::SurfaceDistanceOptions options;
    options.sampling.sample_count = 200000;
    double previous = 1e300;
    for (std::uint32_t rows : {64u, 128u, 256u, 512u}) {
        const auto image = passes::cylinder_scanline(cyl, 2 * rows, rows);
        const geo::Mesh back = passes::reconstruct_cpu(image, frame);
        const geo::SurfaceDistance d = geo::surface_distance(mesh, back, options);
        const double rms = d.symmetric.rms / d.bbox_diagonal;
        std::printf("%s %ux%u: symmetric RMS %.4e of the diagonal\n", GetParam(), 2 * rows, rows, rms);
        EXPECT_LT(rms, previous) << rows << " rows";
        previous = rms;
    }
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, RoundtripError, ::testing::Values("cow.off", "homer.off", "triceratops.off"),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                             std::string name = p.param;
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

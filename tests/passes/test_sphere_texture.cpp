// Spherical texture coordinates for checker.png: the right angles, and no triangle wraps round.
#include "gimg/passes/sphere.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace gimg;

TEST(SphereTexture, CoordinatesAreLongitudeAndColatitude) {
    geo::Mesh mesh;
    mesh.positions = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    mesh.triangles = {{0, 1, 2}};
    const geo::Mesh out = passes::spherical_texture_mesh(mesh, mesh.positions);
    ASSERT_GE(out.texcoords.size(), 4u);
    EXPECT_NEAR(out.texcoords[0].x, 0.0, 1e-12);
    EXPECT_NEAR(out.texcoords[1].x, 0.25, 1e-12);
    EXPECT_NEAR(out.texcoords[0].y, 0.25, 1e-12);  // equator: colatitude pi/2 over 2 pi
    EXPECT_NEAR(out.texcoords[2].y, 0.0, 1e-12);
    EXPECT_NEAR(out.texcoords[3].y, 0.5, 1e-12);
}

TEST(SphereTexture, SeamVerticesAreDuplicatedSoNoTriangleWrapsAround) {
    const geo::Mesh mesh = geo::make_icosphere(1.0, 3);
    const geo::Mesh out = passes::spherical_texture_mesh(mesh, mesh.positions);
    ASSERT_EQ(out.face_count(), mesh.face_count());
    EXPECT_GT(out.vertex_count(), mesh.vertex_count()) << "the seam must have been cut";
    for (std::size_t f = 0; f < out.face_count(); ++f) {
        const glm::uvec3 a = mesh.triangles[f], b = out.triangles[f];
        double lo = 2.0, hi = -1.0;
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(out.positions[b[k]], mesh.positions[a[k]]) << "face " << f;
            lo = std::min(lo, out.texcoords[b[k]].x);
            hi = std::max(hi, out.texcoords[b[k]].x);
        }
        // A triangle at a pole spans every longitude; near the poles they are wide; away from
        // them (|y| < 0.7 at all corners) narrow, on either side of the seam.
        double polar = 0.0;
        for (int k = 0; k < 3; ++k) polar = std::max(polar, std::abs(mesh.positions[a[k]].y));
        if (polar < 0.999) {
            EXPECT_LT(hi - lo, 0.5) << "face " << f;
        }
        if (polar < 0.7) {
            EXPECT_LE(hi - lo, 0.05) << "face " << f;
        }
    }
}

TEST(SphereTexture, MismatchedPointsAreAnInputError) {
    const geo::Mesh mesh = geo::make_icosphere(1.0, 1);
    EXPECT_THROW(passes::spherical_texture_mesh(mesh, {glm::dvec3(1, 0, 0)}), geo::InputError);
}

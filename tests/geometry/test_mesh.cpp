#include "gimg/geometry/mesh.h"

#include <gtest/gtest.h>

using gimg::geo::Mesh;

TEST(Mesh, BoundsAndDiagonal) {
    Mesh m;
    m.positions = {{0, 0, 0}, {3, 0, 0}, {0, 4, 0}};
    m.triangles = {{0, 1, 2}};
    auto b = m.bounds();
    EXPECT_EQ(b.max.x, 3.0);
    EXPECT_EQ(b.max.y, 4.0);
    EXPECT_DOUBLE_EQ(b.diagonal(), 5.0);
    EXPECT_DOUBLE_EQ(Mesh{}.bounds().diagonal(), 0.0);
}

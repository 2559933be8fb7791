// Polycube retries against their time (PolycubeOptions::retry_seconds): none starts once it is
// spent, and one still running then stops, the first attempt's failure coming back cut short.
#include "test_data.h"

#include "gimg/geometry/io.h"
#include "gimg/passes/polycube.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

using namespace gimg;
namespace gp = gimg::passes;

// Past retry_seconds no further attempt starts: the femur's failed first attempt is returned as it
// is, no retry announced, and says that the retries were cut short.
TEST(PolycubeSharedMeshes, NoRetryStartsOnceTheRetryTimeIsSpent) {
    GIMG_REQUIRE_SHARED_MESH(femur, "femur.off");
    gp::PolycubeOptions o;
    o.retry_seconds = 0.0;
    std::size_t announced = 0;
    const gp::Polycube p =
        gp::build_polycube(nullptr, geo::load_mesh(femur), o, [&](const gp::PolycubeStatistics&) { ++announced; });
    EXPECT_EQ(announced, 0u);
    EXPECT_EQ(p.stats.attempts, 1u);
    EXPECT_EQ(p.stats.axes_tried, 1u);
    EXPECT_TRUE(p.stats.retries_cut_short);
    EXPECT_FALSE(gp::failure_of(p.stats, true).empty());
    EXPECT_EQ(p.stats.slice_smoothing, 0u);
}

// A retry still running once retry_seconds have passed stops at its first check. With the quadtree
// at level 1 the double torus's first two attempts fail and the third (level 10) succeeds; here the
// second starts just past the time (the announcement of the first failure sleeps), so it stops and
// the first attempt's failure comes back, cut short, with no third attempt.
TEST(PolycubeSharedMeshes, ARetryRunningPastTheRetryTimeStops) {
    GIMG_REQUIRE_SHARED_MESH(eight, "eight.off");
    const geo::Mesh mesh = geo::load_mesh(eight);
    gp::PolycubeOptions o;
    o.axis = 2;
    o.max_level = 1;
    o.retry_seconds = 1e6;
    ASSERT_EQ(gp::build_polycube(nullptr, mesh, o).stats.attempts, 3u);  // the case as described
    o.retry_seconds = 0.0;
    const double first = gp::build_polycube(nullptr, mesh, o).stats.seconds;
    o.retry_seconds = 3.0 * first + 0.2;
    using Clock = std::chrono::steady_clock;
    const auto begun = Clock::now();
    std::size_t announced = 0;
    const gp::Polycube p = gp::build_polycube(nullptr, mesh, o, [&](const gp::PolycubeStatistics&) {
        ++announced;
        std::this_thread::sleep_until(
            begun + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.retry_seconds + 0.05)));
    });
    EXPECT_EQ(announced, 1u);
    EXPECT_EQ(p.stats.attempts, 2u);
    EXPECT_TRUE(p.stats.retries_cut_short);
    EXPECT_FALSE(gp::failure_of(p.stats, true).empty());
    EXPECT_EQ(p.stats.slice_smoothing, 0u);  // the first attempt's
    EXPECT_EQ(p.stats.max_level, 1u);
}

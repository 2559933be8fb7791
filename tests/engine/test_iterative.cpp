// Iterative passes: 1D Jacobi diffusion for 1,000 iterations as 20 executions of one compiled
// graph, each running a loop of K = 50 ping-pong iterations; equal to the CPU within 1e-6.
#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"

#include "gpu_test.h"

#include "engine/jacobi1d_comp.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

using namespace gimg;

class IterativePass : public gimg::test::GpuTest {};

namespace {
const Spirv kJacobi = GIMG_SPIRV(gimg_spv_engine_jacobi1d_comp);

struct JacobiPush {
    std::uint32_t count;
    float alpha;
};

std::vector<float> jacobi_cpu(std::vector<float> u, float alpha, int iterations) {
    std::vector<float> next(u.size());
    for (int it = 0; it < iterations; ++it) {
        next.front() = u.front();
        next.back() = u.back();
        for (std::size_t i = 1; i + 1 < u.size(); ++i) {
            const float l = u[i - 1], c = u[i], r = u[i + 1];
            next[i] = c + alpha * ((l - c) + (r - c));
        }
        u.swap(next);
    }
    return u;
}

// K Jacobi iterations ping-ponging between a and b (K even: the result lands in a).
Plan jacobi_plan(Context& ctx, Buffer& a, Buffer& b, std::uint32_t n, std::uint32_t k, float alpha) {
    Graph g(ctx);
    auto ha = g.import_buffer(a);
    auto hb = g.import_buffer(b);
    g.add_loop(k, [&] {
        g.add_compute_pass(
            "jacobi",
            [&](PassBuilder& p) {
                ha = p.write(ha, Access::ComputeReadWrite);
                hb = p.write(hb, Access::ComputeReadWrite);
            },
            [=](Cmd& c) {
                const bool even = c.iteration() % 2 == 0;  // even iterations read a, odd ones read b
                c.dispatch_threads(kJacobi, {n}, {even ? ha : hb, even ? hb : ha}, JacobiPush{n, alpha});
            });
    });
    g.export_buffer(ha, Access::TransferSrc);
    return g.compile();
}
}  // namespace

TEST_F(IterativePass, JacobiDiffusionInChunksOfFiftyMatchesTheCpu) {
    constexpr std::uint32_t N = 1000, K = 50, kExecutions = 20;
    constexpr float kAlpha = 0.25f;
    std::vector<float> initial(N);
    for (std::uint32_t i = 0; i < N; ++i) initial[i] = (i % 97 == 0 ? 1.0f : 0.0f) + 0.5f * std::sin(0.05f * float(i));

    Buffer a = ctx().create_buffer({N * sizeof(float), "u (even)"});
    Buffer b = ctx().create_buffer({N * sizeof(float), "u (odd)"});
    ctx().upload(a, initial.data(), N * sizeof(float));

    Plan plan = jacobi_plan(ctx(), a, b, N, K, kAlpha);
    for (std::uint32_t e = 0; e < kExecutions; ++e) plan.execute({.wait = false, .timestamps = e + 1 == kExecutions});

    const std::vector<float> gpu = ctx().download<float>(a);  // K is even: the result is in a
    const std::vector<float> cpu = jacobi_cpu(initial, kAlpha, int(K * kExecutions));
    double worst = 0.0;
    for (std::uint32_t i = 0; i < N; ++i) worst = std::max(worst, double(std::abs(gpu[i] - cpu[i])));
    EXPECT_LE(worst, 1e-6);
    // The diffusion did something: the result is not the input.
    double change = 0.0;
    for (std::uint32_t i = 0; i < N; ++i) change = std::max(change, double(std::abs(cpu[i] - initial[i])));
    EXPECT_GT(change, 0.1);

    const auto& timings = plan.timings();
    ASSERT_EQ(timings.size(), 1u);
    EXPECT_EQ(timings[0].name, "jacobi");
    EXPECT_EQ(timings[0].iterations, K);
    EXPECT_GT(timings[0].gpu_ms, 0.0);
}

// Plan::finished() polls without waiting: false while 2,000 passes run, true once they are done,
// and the result is the one waiting gives.
TEST_F(IterativePass, FinishedTurnsTrueWhenTheExecutionIsDone) {
    constexpr std::uint32_t N = 1000, K = 2000;
    constexpr float kAlpha = 0.25f;
    std::vector<float> initial(N);
    for (std::uint32_t i = 0; i < N; ++i) initial[i] = i % 97 == 0 ? 1.0f : 0.0f;
    Buffer a = ctx().create_buffer({N * sizeof(float), "u (even)"});
    Buffer b = ctx().create_buffer({N * sizeof(float), "u (odd)"});
    ctx().upload(a, initial.data(), N * sizeof(float));
    Plan plan = jacobi_plan(ctx(), a, b, N, K, kAlpha);
    EXPECT_TRUE(plan.finished());  // nothing executed yet
    plan.execute({.wait = false});
    EXPECT_FALSE(plan.finished());
    const auto start = std::chrono::steady_clock::now();
    while (!plan.finished())
        ASSERT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60)) << "never finished";
    const std::vector<float> gpu = ctx().download<float>(a);
    const std::vector<float> cpu = jacobi_cpu(initial, kAlpha, int(K));
    for (std::uint32_t i = 0; i < N; ++i) ASSERT_NEAR(gpu[i], cpu[i], 1e-6) << i;
}

// Context::device_wait_seconds counts the host's time blocked on unfinished work: a wait on 2,000
// passes adds time, at most what the wait took; a wait on work already done adds none. The
// execution is one submission.
TEST_F(IterativePass, DeviceWaitCountsOnlyWaitsOnUnfinishedWork) {
    constexpr std::uint32_t N = 1000, K = 2000;
    Buffer a = ctx().create_buffer({N * sizeof(float), "u (even)"});
    Buffer b = ctx().create_buffer({N * sizeof(float), "u (odd)"});
    const std::vector<float> zeros(N, 0.0f);
    ctx().upload(a, zeros.data(), N * sizeof(float));
    Plan plan = jacobi_plan(ctx(), a, b, N, K, 0.25f);
    ctx().wait_idle();
    const std::uint64_t submitted = ctx().submission_count();
    const double before = ctx().device_wait_seconds();
    plan.execute({.wait = false});
    EXPECT_EQ(ctx().submission_count(), submitted + 1);
    EXPECT_FALSE(plan.finished());
    const auto start = std::chrono::steady_clock::now();
    plan.wait();
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double counted = ctx().device_wait_seconds() - before;
    EXPECT_GT(counted, 0.0);
    EXPECT_LE(counted, waited);
    const double after = ctx().device_wait_seconds();
    plan.wait();
    ctx().wait_idle();
    EXPECT_EQ(ctx().device_wait_seconds(), after) << "waits on finished work count nothing";
}

// A wait polls the timeline before it sleeps (ContextOptions::wait_spin_us): not on a CPU device by
// default; when asked, it returns as soon as the work is done, whether that is within the polling
// budget or after it, with the result and the counted wait of a sleeping wait.
TEST_F(IterativePass, AWaitThatPollsFirstReturnsWhenTheWorkIsDone) {
    const bool cpu_device = ctx().device_info().type == VK_PHYSICAL_DEVICE_TYPE_CPU;
    if (!std::getenv("GIMG_WAIT_SPIN_US")) {
        EXPECT_EQ(ctx().wait_spin_us(), cpu_device ? 0u : 1000u);
    }
    const std::uint32_t chosen = ctx().wait_spin_us();
    constexpr std::uint32_t N = 1000, K = 2000;
    constexpr float kAlpha = 0.25f;
    std::vector<float> initial(N);
    for (std::uint32_t i = 0; i < N; ++i) initial[i] = std::sin(0.05f * float(i));
    const std::vector<float> cpu = jacobi_cpu(initial, kAlpha, int(K));
    Buffer a = ctx().create_buffer({N * sizeof(float), "u (even)"});
    Buffer b = ctx().create_buffer({N * sizeof(float), "u (odd)"});
    Plan plan = jacobi_plan(ctx(), a, b, N, K, kAlpha);
    // 200 us: shorter than 2,000 passes take, so the wait polls, then sleeps; 10 s: the work ends first.
    for (std::uint32_t spin : {200u, 10'000'000u}) {
        SCOPED_TRACE("spin " + std::to_string(spin) + " us");
        ctx().set_wait_spin_us(spin);
        EXPECT_EQ(ctx().wait_spin_us(), spin);
        ctx().upload(a, initial.data(), N * sizeof(float));
        ctx().wait_idle();
        const double before = ctx().device_wait_seconds();
        const auto start = std::chrono::steady_clock::now();
        plan.execute();
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        EXPECT_TRUE(plan.finished()) << "the wait returned before the work was done";
        const double counted = ctx().device_wait_seconds() - before;
        EXPECT_GT(counted, 0.0);
        EXPECT_LE(counted, seconds);
        EXPECT_LT(seconds, 5.0) << "the wait ended with the work, not with its polling budget";
        const std::vector<float> gpu = ctx().download<float>(a);
        double worst = 0.0;
        for (std::uint32_t i = 0; i < N; ++i) worst = std::max(worst, double(std::abs(gpu[i] - cpu[i])));
        EXPECT_LE(worst, 1e-6);
    }
    ctx().set_wait_spin_us(chosen);
}

TEST(ContextOptionsFromEnvironment, ReadsTheWaitSpinAndRefusesWhatIsNotANumber) {
    const char* set = std::getenv("GIMG_WAIT_SPIN_US");
    const std::optional<std::string> outside = set ? std::optional<std::string>(set) : std::nullopt;
    ::setenv("GIMG_WAIT_SPIN_US", "250", 1);
    EXPECT_EQ(ContextOptions::from_environment().wait_spin_us, std::optional<std::uint32_t>(250u));
    for (const char* bad : {"abc", "12us", "", "2000000"}) {
        ::setenv("GIMG_WAIT_SPIN_US", bad, 1);
        EXPECT_THROW(ContextOptions::from_environment(), gimg::Error) << bad;
    }
    ::unsetenv("GIMG_WAIT_SPIN_US");
    EXPECT_FALSE(ContextOptions::from_environment().wait_spin_us.has_value());
    if (outside) ::setenv("GIMG_WAIT_SPIN_US", outside->c_str(), 1);  // as the run set it
}

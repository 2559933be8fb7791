// gimg bench engine: what the host pays per submission on this device. Iterative GPU paths (the
// solvers' convergence checks, quad-region edits, the hierarchy's levels) read results back
// between submissions, so a round trip bounds how fast they can be whatever their passes cost.
#include "command_files.h"
#include "commands.h"
#include "gpu_context.h"
#include "json_output.h"
#include "timing.h"

#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"
#include "gimg/passes/primitives.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

namespace gimg::cli {

namespace {

struct EngineBenchOptions {
    std::uint32_t runs = 200;
    std::uint32_t chain = 32;
    std::string json;
};

// Median and the 10th and 90th percentiles, in microseconds, of times in milliseconds.
nlohmann::json spread_us(std::vector<double> ms) {
    std::sort(ms.begin(), ms.end());
    auto at = [&](double q) { return 1000.0 * ms[std::size_t(q * double(ms.size() - 1) + 0.5)]; };
    return {{"median", 1000.0 * median(ms)}, {"p10", at(0.1)}, {"p90", at(0.9)}};
}

void run_engine_bench(const EngineBenchOptions& o, const GlobalOptions& global) {
    const auto context = open_context(global);
    Context& ctx = *context;
    constexpr std::uint32_t kCount = 64;  // one workgroup's sum
    Buffer data = ctx.create_buffer({kCount * sizeof(std::uint32_t), "bench numbers"});
    Buffer ping = ctx.create_buffer({sizeof(std::uint32_t), "bench sum a"});
    Buffer pong = ctx.create_buffer({sizeof(std::uint32_t), "bench sum b"});
    const std::vector<std::uint32_t> ones(kCount, 1u);
    ctx.upload(data, ones.data(), ones.size() * sizeof(std::uint32_t));

    // One pass: the sum of 64 numbers.
    Graph one_graph(ctx);
    passes::add_reduce_sum(one_graph, one_graph.import_buffer(data), one_graph.import_buffer(ping), kCount);
    Plan one = one_graph.compile();
    // `chain` dependent passes: the sum, then each pass copying the last one's result (a sum of one).
    Graph chain_graph(ctx);
    BufferHandle last =
        passes::add_reduce_sum(chain_graph, chain_graph.import_buffer(data), chain_graph.import_buffer(ping), kCount);
    BufferHandle other = chain_graph.import_buffer(pong);
    for (std::uint32_t i = 1; i < o.chain; ++i) {
        BufferHandle next = passes::add_reduce_sum(chain_graph, last, other, 1, "link " + std::to_string(i));
        other = last;
        last = next;
    }
    Plan chain = chain_graph.compile();

    std::vector<double> wait_ms, poll_ms, idle_ms, upload_ms, download_ms, chain_ms, chain_timed_ms, chain_gpu_ms;
    std::vector<double> sleeping_ms, polling_ms;
    std::uint32_t value = 0;
    const std::uint32_t spin = ctx.wait_spin_us();
    // The same round trip with the host thread asleep in the wait at once, and polling for up to 1 ms
    // first (ContextOptions::wait_spin_us), whatever this device's default.
    auto with_spin = [&](std::uint32_t us) {
        ctx.set_wait_spin_us(us);
        const double ms = time_ms([&] { one.execute(); });
        ctx.set_wait_spin_us(spin);
        return ms;
    };
    for (std::uint32_t r = 0; r <= o.runs; ++r) {  // run 0 warms up (pipelines, transients)
        const double w = time_ms([&] { one.execute(); });
        const double sleeping = with_spin(0);
        const double polling = with_spin(1000);
        const double p = time_ms([&] {
            one.execute({.wait = false});
            while (!one.finished()) {}
        });
        std::this_thread::sleep_for(std::chrono::milliseconds(5));  // the device idles
        const double i = time_ms([&] { one.execute(); });
        const double d = time_ms([&] { ctx.download(ping, &value, sizeof value); });
        const double u = time_ms([&] { ctx.upload(pong, &value, sizeof value); });
        const double c = time_ms([&] { chain.execute(); });
        const double ct = time_ms([&] { chain.execute({.wait = true, .timestamps = true}); });
        if (r == 0) continue;
        if (value != kCount)
            throw gimg::Error(ErrorKind::Vulkan, "bench engine: the pass summed 64 ones to " + std::to_string(value));
        wait_ms.push_back(w);
        sleeping_ms.push_back(sleeping);
        polling_ms.push_back(polling);
        poll_ms.push_back(p);
        idle_ms.push_back(i);
        download_ms.push_back(d);
        upload_ms.push_back(u);
        chain_ms.push_back(c);
        chain_timed_ms.push_back(ct);
        chain_gpu_ms.push_back(chain.total_gpu_ms());
    }
    std::uint32_t chained = 0;
    ctx.download(chain.buffer(last), &chained, sizeof chained);
    if (chained != kCount)
        throw gimg::Error(ErrorKind::Vulkan,
                          "bench engine: the chain passed on " + std::to_string(chained) + ", not 64");

    const double per_pass_us = 1000.0 * median(chain_ms) / double(o.chain);
    const bool timed = ctx.device_info().timestamp_period_ns > 0.0;
    std::printf("gimg bench engine on %s: microseconds, medians of %u (10th-90th percentile)\n",
                ctx.device_info().name.c_str(), o.runs);
    auto row = [](const char* what, const std::vector<double>& ms) {
        const nlohmann::json s = spread_us(ms);
        std::printf("  %-56s %9.1f  (%.1f-%.1f)\n", what, s["median"].get<double>(), s["p10"].get<double>(),
                    s["p90"].get<double>());
        return s;
    };
    nlohmann::json j{{"runs", o.runs}, {"chain", o.chain}};
    j["wait_spin_us"] = spin;
    j["execute_wait_us"] =
        row(("one pass, executed and waited for (" + std::to_string(spin) + " us polled first)").c_str(), wait_ms);
    j["execute_sleeping_wait_us"] = row("the same, the wait asleep at once", sleeping_ms);
    j["execute_polling_wait_us"] = row("the same, up to 1000 us polled first", polling_ms);
    j["execute_poll_us"] = row("the same, finished() polled", poll_ms);
    j["execute_after_idle_us"] = row("the same after 5 ms idle", idle_ms);
    j["download_us"] = row("a 4-byte download", download_ms);
    j["upload_us"] = row("a 4-byte upload", upload_ms);
    j["chain_us"] = row(("a chain of " + std::to_string(o.chain) + " dependent passes, waited for").c_str(), chain_ms);
    j["chain_timed_us"] = row("the same with timestamps", chain_timed_ms);
    j["per_pass_us"] = per_pass_us;
    j["per_pass_gpu_us"] = timed ? nlohmann::json(1000.0 * median(chain_gpu_ms) / double(o.chain)) : nullptr;
    std::printf("  per pass in the chain: %.1f wall", per_pass_us);
    if (timed) std::printf(", %.1f by timestamps", j["per_pass_gpu_us"].get<double>());
    std::printf("\n");
    add_machine_figures(j, &ctx);
    write_json(o.json, j);
}

}  // namespace

void add_bench_engine_command(CLI::App& bench, const GlobalOptions& global) {
    auto o = std::make_shared<EngineBenchOptions>();
    auto* cmd = bench.add_subcommand("engine",
                                     "What a submission costs: round trips (waited for, polled, after idling), "
                                     "4-byte uploads and downloads, a pass in a chain");
    add_count_option(cmd, "--runs", o->runs, 1, 100000, "Timed runs of each; medians (default 200)");
    add_count_option(cmd, "--chain", o->chain, 2, 4096, "Dependent passes in the chain (default 32)");
    cmd->add_option("--json", o->json, "Write the figures as JSON");
    cmd->callback([o, &global] { run_writing({}, {json_output(o->json)}, [&] { run_engine_bench(*o, global); }); });
}

}  // namespace gimg::cli

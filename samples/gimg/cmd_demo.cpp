// gimg demo: the engine's smallest end-to-end example. Later capabilities give the demo a real
// job; until then it runs a prefix sum and a reduction over a million integers on the render
// graph, checks them against the CPU and reports the GPU time per pass.
#include "commands.h"
#include "gpu_context.h"

#include "gimg/engine/graph.h"
#include "gimg/passes/primitives.h"

#include <cstdio>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace gimg::cli {

void add_demo_command(CLI::App& app, const GlobalOptions& global) {
    auto* cmd = app.add_subcommand("demo", "Run the engine's smallest end-to-end example");
    cmd->callback([&global] {
        auto ctx = open_context(global);
        const std::uint32_t n = 1u << 20;
        std::vector<std::uint32_t> values(n);
        for (std::uint32_t i = 0; i < n; ++i) values[i] = (i * 2654435761u >> 13) % 1000;

        Buffer in = ctx->create_buffer({n * 4ull, "values"});
        Buffer sums = ctx->create_buffer({n * 4ull, "prefix sums"});
        Buffer total = ctx->create_buffer({4, "total"}, MemoryUsage::Readback);
        ctx->upload(in, values.data(), n * 4ull);
        Graph g(*ctx);
        auto hin = g.import_buffer(in);
        auto hs = passes::add_inclusive_scan(g, hin, g.import_buffer(sums), n);
        auto ht = passes::add_reduce_sum(g, hin, g.import_buffer(total), n);
        g.export_buffer(hs, Access::TransferSrc);
        g.export_buffer(ht, Access::HostRead);
        Plan plan = g.compile();
        plan.execute({.timestamps = true});

        std::vector<std::uint32_t> expected(n);
        std::inclusive_scan(values.begin(), values.end(), expected.begin());
        const bool ok = ctx->download<std::uint32_t>(sums) == expected && total.mapped_as<std::uint32_t>()[0] == expected.back();
        if (!global.quiet) {
            std::printf("gimg demo: the engine's smallest end-to-end example (the geometry-image demos "
                        "replace it as they land)\n");
            std::printf("device: %s\n", ctx->device_info().summary().c_str());
            std::printf("prefix sum and sum of %u integers on the render graph, %zu passes:\n", n, plan.passes().size());
            for (const PassTiming& t : plan.timings()) std::printf("  %-28s %8.3f ms GPU\n", t.name.c_str(), t.gpu_ms);
            std::printf("total %.3f ms GPU; %s the CPU\n", plan.total_gpu_ms(), ok ? "equal to" : "DIFFERENT FROM");
        }
        if (!ok) throw std::runtime_error("the GPU result differs from the CPU");
    });
}

}  // namespace gimg::cli

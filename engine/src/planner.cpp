// compile(): which passes run, in what order, what each one does to each resource, and for how
// long every transient must live.
#include "planner.h"

#include "gimg/engine/context.h"

#include "device.h"

#include <algorithm>

namespace gimg::detail {

namespace {

// Passes that must run: kept ones, writers of imported or exported resources, and everything
// they depend on. A loop runs whole or not at all (its iterations feed each other).
std::vector<bool> live_passes(const GraphData& g) {
    std::vector<bool> live(g.passes.size(), false);
    std::vector<std::uint32_t> work;
    auto mark = [&](std::uint32_t p) {
        if (!live[p]) live[p] = true, work.push_back(p);
    };
    for (std::uint32_t p = 0; p < g.passes.size(); ++p) {
        const PassDecl& pass = g.passes[p];
        bool root = pass.keep;
        for (const AccessDecl& a : pass.accesses) {
            const ResourceDecl& r = g.resources[a.resource];
            if (access_info(a.access).writes && (r.imported() || r.export_access)) root = true;
        }
        if (root) mark(p);
    }
    while (!work.empty()) {
        std::uint32_t p = work.back();
        work.pop_back();
        for (std::uint32_t dep : g.passes[p].depends_on) mark(dep);
        if (int l = g.passes[p].loop; l >= 0)
            for (std::uint32_t q = g.loops[l].first_pass; q < g.loops[l].end_pass; ++q) mark(q);
    }
    return live;
}

// One Use per resource per pass: the pass's declarations of that resource merged.
std::vector<Use> merge_uses(const GraphData& g, const PassDecl& pass) {
    std::vector<Use> uses;
    for (const AccessDecl& a : pass.accesses) {
        AccessInfo info = access_info(a.access);
        auto it = std::find_if(uses.begin(), uses.end(), [&](const Use& u) { return u.resource == a.resource; });
        if (it == uses.end()) {
            uses.push_back({a.resource, info, false});
            continue;
        }
        if (g.resources[a.resource].image && it->info.layout != info.layout)
            g.fail("pass '" + pass.name + "' uses image '" + g.resources[a.resource].name() +
                   "' in two layouts at once (" + to_string(a.access) + " and an earlier access)");
        it->info.stages |= info.stages;
        it->info.access |= info.access;
        it->info.reads |= info.reads;
        it->info.writes |= info.writes;
    }
    // A cleared attachment overwrites everything: its old contents need not be kept.
    auto cleared = [&](std::uint32_t r) {
        for (const auto& c : pass.colors)
            if (c.resource == r && c.clear) return true;
        return pass.depth && pass.depth->resource == r && pass.depth->clear.has_value();
    };
    for (Use& u : uses) u.discard = cleared(u.resource);
    return uses;
}

VkImageUsageFlags image_usage_of(Access a) {
    switch (a) {
        case Access::ComputeRead:
        case Access::ComputeWrite:
        case Access::ComputeReadWrite:
        case Access::FragmentRead:
        case Access::FragmentWrite:
        case Access::FragmentReadWrite:
        case Access::VertexRead:
            return VK_IMAGE_USAGE_STORAGE_BIT;
        case Access::ComputeSampled:
        case Access::FragmentSampled:
            return VK_IMAGE_USAGE_SAMPLED_BIT;
        case Access::ColorAttachment:
            return VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
        case Access::DepthAttachment:
            return VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
        case Access::TransferSrc:
            return VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        case Access::TransferDst:
            return VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        default:
            return 0;
    }
}

}  // namespace

PlanData::~PlanData() {
    if (!device) return;
    try {
        device->wait(submitted);
    } catch (...) {
        // Device lost: nothing left to wait for; free what we can.
    }
    for (auto& p : physicals) {
        p.buffer = Buffer();
        p.image_object = Image();
    }
    for (auto& b : blocks) device->allocator.free(b);
    if (cmd) device->fn.vkFreeCommandBuffers(device->device, device->command_pool, 1, &cmd);
    if (query_pool) device->fn.vkDestroyQueryPool(device->device, query_pool, nullptr);
}

std::unique_ptr<PlanData> plan_graph(Context* ctx, GraphData&& graph) {
    auto plan = std::make_unique<PlanData>();
    plan->ctx = ctx;
    plan->graph = std::move(graph);
    const GraphData& g = plan->graph;
    if (g.open_loop >= 0) g.fail("compile() inside add_loop()");

    // Order and culling: declaration order is a valid order (a handle exists before its use).
    std::vector<bool> live = live_passes(g);
    std::vector<int> loop_map(g.loops.size(), -1);
    for (std::uint32_t p = 0; p < g.passes.size(); ++p) {
        if (!live[p]) {
            plan->culled.push_back(g.passes[p].name);
            continue;
        }
        CompiledPass cp;
        cp.decl = p;
        cp.uses = merge_uses(g, g.passes[p]);
        if (int l = g.passes[p].loop; l >= 0) {
            if (loop_map[l] < 0) {
                loop_map[l] = int(plan->loops.size());
                plan->loops.push_back({g.loops[l].iterations, std::uint32_t(plan->passes.size()), 0});
            }
            cp.loop = loop_map[l];
            plan->loops[cp.loop].end = std::uint32_t(plan->passes.size() + 1);
        }
        plan->passes.push_back(std::move(cp));
    }

    // Lifetimes per logical resource, widened to whole loops, and each transient's first use
    // (which may discard what the memory held).
    const std::uint32_t n = std::uint32_t(plan->passes.size());
    std::vector<std::uint32_t> first(g.resources.size(), UINT32_MAX), last(g.resources.size(), 0);
    std::vector<VkImageUsageFlags> usage(g.resources.size(), 0);
    for (std::uint32_t i = 0; i < n; ++i) {
        const CompiledPass& cp = plan->passes[i];
        std::uint32_t lo = i, hi = i;
        if (cp.loop >= 0) lo = plan->loops[cp.loop].first, hi = plan->loops[cp.loop].end - 1;
        for (const Use& u : cp.uses) {
            first[u.resource] = std::min(first[u.resource], lo);
            last[u.resource] = std::max(last[u.resource], hi);
        }
        for (const AccessDecl& a : g.passes[cp.decl].accesses) usage[a.resource] |= image_usage_of(a.access);
    }
    for (std::uint32_t r = 0; r < g.resources.size(); ++r)
        if (g.resources[r].image && g.resources[r].export_access)
            usage[r] |= image_usage_of(*g.resources[r].export_access);
    std::vector<bool> seen(g.resources.size(), false);
    for (CompiledPass& cp : plan->passes) {
        for (Use& u : cp.uses) {
            if (!seen[u.resource] && !g.resources[u.resource].imported()) u.discard = true;
            seen[u.resource] = true;
        }
    }

    assign_physical_resources(*plan, {first, last, usage});

    for (const CompiledPass& cp : plan->passes)
        for (const AccessDecl& a : plan->graph.passes[cp.decl].accesses)
            if (plan->physical_of[a.resource] >= 0)
                plan->physicals[plan->physical_of[a.resource]].last_access = a.access;

    plan->device = ctx ? &ctx->device() : nullptr;
    place_transient_memory(*plan);

    // Inspection: the first execution's barriers; its end states start the later executions.
    Schedule s = schedule_barriers(*plan, start_states(*plan, true));
    plan->wrap_states = s.end;
    for (std::uint32_t i = 0; i < n; ++i) {
        const CompiledPass& cp = plan->passes[i];
        PlannedPass pp;
        pp.name = g.passes[cp.decl].name;
        pp.raster = g.passes[cp.decl].raster;
        pp.iterations = cp.loop >= 0 ? plan->loops[cp.loop].iterations : 1;
        for (const Barrier& b : s.before[i]) pp.barriers.push_back(describe_barrier(*plan, b));
        for (const Barrier& b : s.repeat[i]) pp.repeat_barriers.push_back(describe_barrier(*plan, b));
        plan->planned.push_back(std::move(pp));
    }
    for (const Barrier& b : s.final_barriers) plan->final_infos.push_back(describe_barrier(*plan, b));
    return plan;
}

}  // namespace gimg::detail

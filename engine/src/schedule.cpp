// The barriers of one execution: replay every use in recording order (loops twice: once for the
// first iteration, once for the later ones) through the one barrier rule.
#include "planner.h"

namespace gimg::detail {

namespace {

void step(const PlanData& plan, std::vector<SyncState>& states, const Use& use, bool first_iteration,
          std::vector<Barrier>& out) {
    const std::int32_t p = plan.physical_of[use.resource];
    const bool discard = use.discard && first_iteration;
    SyncState& s = states[p];
    if (discard)  // the memory's previous occupants must be done before it is reused
        for (std::uint32_t q : plan.physicals[p].shares_memory_with) s.merge(states[q]);
    if (auto b = advance(s, use.info, plan.physicals[p].image, discard)) {
        b->resource = std::uint32_t(p);
        out.push_back(*b);
    }
}

}  // namespace

Schedule schedule_barriers(const PlanData& plan, std::vector<SyncState> states) {
    Schedule s;
    const std::size_t n = plan.passes.size();
    s.before.resize(n);
    s.repeat.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const CompiledPass& cp = plan.passes[i];
        for (const Use& u : cp.uses) step(plan, states, u, true, s.before[i]);
        if (cp.loop < 0) continue;
        const CompiledLoop& loop = plan.loops[cp.loop];
        if (i + 1 != loop.end || loop.iterations < 2) continue;
        // Iteration two onwards starts from the state the body leaves, and leaves it the same.
        for (std::size_t j = loop.first; j < loop.end; ++j)
            for (const Use& u : plan.passes[j].uses) step(plan, states, u, false, s.repeat[j]);
    }
    for (std::uint32_t r = 0; r < plan.graph.resources.size(); ++r) {
        const ResourceDecl& d = plan.graph.resources[r];
        const std::int32_t p = plan.physical_of[r];
        if (!d.export_access || p < 0) continue;
        if (auto b = advance(states[p], access_info(*d.export_access), d.image, false)) {
            b->resource = std::uint32_t(p);
            s.final_barriers.push_back(*b);
        }
    }
    s.end = std::move(states);
    return s;
}

std::vector<SyncState> start_states(const PlanData& plan, bool first_execution) {
    std::vector<SyncState> states(plan.physicals.size());
    for (std::size_t p = 0; p < plan.physicals.size(); ++p) {
        const PhysicalResource& ph = plan.physicals[p];
        if (!ph.imported()) {
            if (!first_execution) states[p] = plan.wrap_states.at(p);
            continue;
        }
        const ResourceDecl& d = plan.graph.resources[ph.import_of];
        states[p] = d.image ? d.imported_image->sync_state() : d.imported_buffer->sync_state();
    }
    return states;
}

BarrierInfo describe_barrier(const PlanData& plan, const Barrier& b) {
    BarrierInfo info;
    info.resource = plan.physicals[b.resource].name;
    info.image = b.image;
    info.src_stages = b.src_stages;
    info.src_access = b.src_access;
    info.dst_stages = b.dst_stages;
    info.dst_access = b.dst_access;
    info.old_layout = b.old_layout;
    info.new_layout = b.new_layout;
    return info;
}

}  // namespace gimg::detail

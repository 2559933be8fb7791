// Which physical resource stands behind each logical one: imports stand for themselves, exported
// transients get their own (the caller reads them after execution), and the other transients
// share one whenever their descriptions match and their lifetimes do not overlap.
#include "planner.h"

#include <algorithm>

namespace gimg::detail {

namespace {

PhysicalResource physical_for(const ResourceDecl& d, std::uint32_t r, const ResourceLifetimes& life) {
    PhysicalResource p;
    p.image = d.image;
    p.buffer_desc = d.buffer_desc;
    p.image_desc = d.image_desc;
    p.image_usage = life.image_usage[r];
    p.first_use = life.first[r];
    p.last_use = life.last[r];
    p.name = d.name();
    p.export_access = d.export_access;
    return p;
}

bool same_description(const PhysicalResource& a, const PhysicalResource& b) {
    if (a.image != b.image) return false;
    if (!a.image) return a.buffer_desc.size == b.buffer_desc.size;
    return a.image_desc.width == b.image_desc.width && a.image_desc.height == b.image_desc.height &&
           a.image_desc.format == b.image_desc.format;
}

}  // namespace

void assign_physical_resources(PlanData& plan, const ResourceLifetimes& life) {
    const GraphData& g = plan.graph;
    const std::uint32_t passes = std::uint32_t(plan.passes.size());
    plan.physical_of.assign(g.resources.size(), -1);
    std::vector<std::uint32_t> transients;  // plain transients, assigned after imports and exports
    for (std::uint32_t r = 0; r < g.resources.size(); ++r) {
        const ResourceDecl& d = g.resources[r];
        const bool used = life.first[r] != UINT32_MAX;
        if (!used && !d.export_access) continue;
        if (!d.imported() && !d.export_access) {
            transients.push_back(r);
            continue;
        }
        PhysicalResource p = physical_for(d, r, life);
        if (!used) p.first_use = p.last_use = 0;
        if (d.imported()) {
            p.import_of = std::int32_t(r);
        } else {
            p.exported = true;  // alive for the whole execution and after it
            p.first_use = 0;
            p.last_use = passes ? passes - 1 : 0;
        }
        plan.physical_of[r] = std::int32_t(plan.physicals.size());
        plan.physicals.push_back(std::move(p));
    }

    // Reuse: in order of first use, take a physical resource of equal description whose last use
    // ended before (the one freed last, to keep the others free for later).
    std::stable_sort(transients.begin(), transients.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return life.first[a] < life.first[b]; });
    const std::uint32_t first_transient = std::uint32_t(plan.physicals.size());
    for (std::uint32_t r : transients) {
        PhysicalResource candidate = physical_for(g.resources[r], r, life);
        int best = -1;
        for (std::uint32_t p = first_transient; p < plan.physicals.size(); ++p) {
            const PhysicalResource& ph = plan.physicals[p];
            if (!same_description(ph, candidate) || ph.last_use >= candidate.first_use) continue;
            if (best < 0 || ph.last_use > plan.physicals[best].last_use) best = int(p);
        }
        if (best < 0) {
            plan.physical_of[r] = std::int32_t(plan.physicals.size());
            plan.physicals.push_back(std::move(candidate));
        } else {
            PhysicalResource& ph = plan.physicals[best];
            ph.last_use = candidate.last_use;
            ph.image_usage |= candidate.image_usage;
            ph.name += "|" + candidate.name;
            plan.physical_of[r] = best;
        }
    }
}

}  // namespace gimg::detail

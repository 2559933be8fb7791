// Memory for a plan's transient resources. Physical resources whose lifetimes do not overlap may
// occupy the same bytes (aliasing); the barrier schedule makes each first use wait for the
// previous occupants. Buffers and images use separate blocks so bufferImageGranularity never
// matters. Exported transients get their own memory: the caller reads them after execution.
#include "planner.h"

#include "check.h"
#include "device.h"

#include <algorithm>
#include <map>

namespace gimg::detail {

namespace {

VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return a ? (v + a - 1) / a * a : v; }

bool lifetimes_overlap(const PhysicalResource& a, const PhysicalResource& b) {
    return !(a.last_use < b.first_use || b.last_use < a.first_use);
}

// Without a device, a plan still shows its placement; estimate what a driver would ask for.
VkMemoryRequirements estimated_requirements(const PhysicalResource& p) {
    VkMemoryRequirements r{};
    r.alignment = 256;
    r.memoryTypeBits = 1;
    r.size = p.image ? VkDeviceSize(p.image_desc.width) * p.image_desc.height * bytes_per_pixel(p.image_desc.format)
                     : p.buffer_desc.size;
    r.size = align_up(r.size, r.alignment);
    return r;
}

struct Item {
    std::uint32_t physical;
    VkMemoryRequirements req;
};

// First fit over the items sorted by size: each goes at the lowest offset that no item with an
// overlapping lifetime occupies.
VkDeviceSize place(PlanData& plan, std::vector<Item>& items, std::uint32_t block) {
    std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.req.size > b.req.size; });
    std::vector<const Item*> placed;
    VkDeviceSize block_size = 0;
    for (Item& item : items) {
        PhysicalResource& p = plan.physicals[item.physical];
        std::vector<VkDeviceSize> candidates{0};
        for (const Item* q : placed) {
            const PhysicalResource& qp = plan.physicals[q->physical];
            if (lifetimes_overlap(p, qp))
                candidates.push_back(align_up(qp.placement->offset + qp.placement->size, item.req.alignment));
        }
        std::sort(candidates.begin(), candidates.end());
        VkDeviceSize offset = 0;
        for (VkDeviceSize c : candidates) {
            const bool free = std::none_of(placed.begin(), placed.end(), [&](const Item* q) {
                const PhysicalResource& qp = plan.physicals[q->physical];
                return lifetimes_overlap(p, qp) && c < qp.placement->offset + qp.placement->size &&
                       qp.placement->offset < c + item.req.size;
            });
            if (free) {
                offset = c;
                break;
            }
        }
        p.placement = MemoryPlacement{block, offset, item.req.size};
        placed.push_back(&item);
        block_size = std::max(block_size, offset + item.req.size);
    }
    for (const Item* a : placed)
        for (const Item* b : placed) {
            if (a == b) continue;
            const MemoryPlacement& pa = *plan.physicals[a->physical].placement;
            const MemoryPlacement& pb = *plan.physicals[b->physical].placement;
            if (pa.offset < pb.offset + pb.size && pb.offset < pa.offset + pa.size)
                plan.physicals[a->physical].shares_memory_with.push_back(b->physical);
        }
    return block_size;
}

}  // namespace

void place_transient_memory(PlanData& plan) {
    Device* d = plan.device;
    // Group by (buffer or image, memory type bits): each group becomes one block.
    std::map<std::pair<bool, std::uint32_t>, std::vector<Item>> groups;
    for (std::uint32_t i = 0; i < plan.physicals.size(); ++i) {
        PhysicalResource& p = plan.physicals[i];
        if (p.imported()) continue;
        VkMemoryRequirements req;
        if (!d) {
            req = estimated_requirements(p);
        } else if (p.image) {
            p.image_object = d->create_image_unbound(p.image_desc, p.image_usage);
            d->fn.vkGetImageMemoryRequirements(d->device, p.image_object.vk(), &req);
        } else {
            p.buffer = d->create_buffer_unbound(p.buffer_desc);
            d->fn.vkGetBufferMemoryRequirements(d->device, p.buffer.vk(), &req);
        }
        if (p.exported) {
            if (!d) continue;
            const MemoryUsage usage =
                p.export_access == Access::HostRead ? MemoryUsage::Readback : MemoryUsage::DeviceLocal;
            plan.blocks.push_back(d->allocator.allocate(req, usage, p.name));
            Allocation a = plan.blocks.back();
            a.owns_memory = false;  // the plan frees the block
            if (p.image)
                d->bind(p.image_object, a);
            else
                d->bind(p.buffer, a);
            continue;
        }
        groups[{p.image, req.memoryTypeBits}].push_back({i, req});
    }
    for (auto& [key, items] : groups) {
        const std::uint32_t block = std::uint32_t(plan.block_sizes.size());
        VkDeviceSize alignment = 1;
        for (const Item& item : items) alignment = std::max(alignment, item.req.alignment);
        plan.block_sizes.push_back(place(plan, items, block));
        if (!d) continue;
        VkMemoryRequirements block_req{plan.block_sizes.back(), alignment, key.second};
        Allocation memory = d->allocator.allocate(block_req, MemoryUsage::DeviceLocal,
                                                  std::string(key.first ? "transient images" : "transient buffers"));
        plan.blocks.push_back(memory);
        for (const Item& item : items) {
            PhysicalResource& p = plan.physicals[item.physical];
            Allocation a = memory;
            a.owns_memory = false;
            a.offset = p.placement->offset;
            a.size = p.placement->size;
            a.mapped = memory.mapped ? static_cast<char*>(memory.mapped) + a.offset : nullptr;
            if (p.image)
                d->bind(p.image_object, a);
            else
                d->bind(p.buffer, a);
        }
    }
}

}  // namespace gimg::detail

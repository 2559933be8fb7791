#pragma once
// gimg's small device-memory allocator. Debian ships no Vulkan allocator library, and gimg's
// needs are simple: persistent resources get dedicated allocations (few, large), and a compiled
// graph asks for one block per aliasing group and places its transients in it itself. Freed
// allocations are kept, up to a budget, for the next request of about their size: on lavapipe
// device memory is heap memory that glibc does not hand back for page-aligned requests, so each
// new allocation faulted its pages in afresh (docs/engine.md).

#include "gimg/engine/memory.h"

#include "vk_dispatch.h"

#include <optional>
#include <string>
#include <vector>

namespace gimg::detail {

class Allocator {
public:
    void init(const DeviceFns* fns, VkDevice device, const VkPhysicalDeviceMemoryProperties& props,
              VkDeviceSize max_allocation_size, VkDeviceSize non_coherent_atom,
              const std::optional<std::uint64_t>& keep_budget);
    // Picks a memory type from `type_bits` suited to `usage`; throws Unsupported if none fits.
    std::uint32_t choose_type(std::uint32_t type_bits, MemoryUsage usage) const;
    // One vkAllocateMemory, mapped when host-visible. `what` names the resource in errors:
    // running out of memory is reported as "out of device memory allocating N MiB for 'what'".
    Allocation allocate(const VkMemoryRequirements& requirements, MemoryUsage usage, const std::string& what);
    // Keeps a dedicated allocation for reuse (the oldest kept ones freed past the budget), or
    // frees it.
    void free(Allocation& allocation);
    // vkFreeMemory for every kept allocation (before the device goes, or when memory runs out).
    void release_kept();
    // Makes host writes visible to the device / device writes visible to the host for
    // non-coherent memory (no-ops on coherent memory). The size is implied: to the allocation's end.
    void flush(const Allocation& allocation, VkDeviceSize offset) const;
    void invalidate(const Allocation& allocation, VkDeviceSize offset) const;
    const MemoryStats& stats() const { return stats_; }

private:
    void count_in(const Allocation& a);  // a live allocation in the stats

    const DeviceFns* fns_ = nullptr;
    VkDevice device_ = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties props_{};
    VkDeviceSize max_allocation_size_ = 0;
    VkDeviceSize non_coherent_atom_ = 1;
    MemoryStats stats_{};
    std::vector<Allocation> kept_;  // freed, still mapped where host-visible; oldest first
    VkDeviceSize keep_budget_ = 0;
};

}  // namespace gimg::detail

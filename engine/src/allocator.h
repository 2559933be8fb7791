#pragma once
// gimg's small device-memory allocator. Debian ships no Vulkan allocator library, and gimg's
// needs are simple: persistent resources get dedicated allocations (few, large), and a compiled
// graph asks for one block per aliasing group and places its transients in it itself.

#include "gimg/engine/memory.h"

#include "vk_dispatch.h"

#include <string>

namespace gimg::detail {

class Allocator {
public:
    void init(const DeviceFns* fns, VkDevice device, const VkPhysicalDeviceMemoryProperties& props,
              VkDeviceSize max_allocation_size, VkDeviceSize non_coherent_atom);
    // Picks a memory type from `type_bits` suited to `usage`; throws Unsupported if none fits.
    std::uint32_t choose_type(std::uint32_t type_bits, MemoryUsage usage) const;
    // One vkAllocateMemory, mapped when host-visible. `what` names the resource in errors:
    // running out of memory is reported as "out of device memory allocating N MiB for 'what'".
    Allocation allocate(const VkMemoryRequirements& requirements, MemoryUsage usage, const std::string& what);
    void free(Allocation& allocation);
    // Makes host writes visible to the device / device writes visible to the host for
    // non-coherent memory (no-ops on coherent memory). The size is implied: to the allocation's end.
    void flush(const Allocation& allocation, VkDeviceSize offset) const;
    void invalidate(const Allocation& allocation, VkDeviceSize offset) const;
    const MemoryStats& stats() const { return stats_; }

private:
    const DeviceFns* fns_ = nullptr;
    VkDevice device_ = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties props_{};
    VkDeviceSize max_allocation_size_ = 0;
    VkDeviceSize non_coherent_atom_ = 1;
    MemoryStats stats_{};
};

}  // namespace gimg::detail

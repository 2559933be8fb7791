#pragma once
// Device memory as gimg's small allocator hands it out. Resources made by Context::create_buffer
// and create_image get dedicated allocations; a compiled render graph places its transient
// resources in shared blocks where their lifetimes allow (aliasing).

#include <vulkan/vulkan.h>

#include <cstdint>

namespace gimg {

// Where a resource's memory should live.
enum class MemoryUsage : std::uint8_t {
    DeviceLocal,  // GPU-only data; uploads and downloads go through staging when not mappable
    Upload,       // host-visible, written by the host, read by the GPU
    Readback,     // host-visible (cached where possible), written by the GPU, read by the host
};

struct Allocation {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;
    void* mapped = nullptr;  // persistent mapping of host-visible memory, at `offset`
    bool coherent = true;
    std::uint32_t memory_type = 0;
    bool owns_memory = false;  // false for a range of a graph's aliasing block
};

struct MemoryStats {
    // Freed allocations that gimg keeps for reuse (up to a sixteenth of the largest heap, at most
    // 256 MiB, released when the Context goes or memory runs out) are not counted.
    std::uint64_t allocated_bytes = 0;       // device memory gimg's live resources hold now
    std::uint64_t peak_allocated_bytes = 0;  // the most they ever held at once
    std::uint32_t allocations = 0;           // live vkAllocateMemory objects
    std::uint64_t kept_bytes = 0;            // freed allocations kept for reuse
};

}  // namespace gimg

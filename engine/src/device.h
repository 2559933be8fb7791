#pragma once
// Everything a Context holds: the Vulkan objects (owned or borrowed), the loaded entry points,
// the allocator, the pipeline cache and the submission timeline. Engine-internal.

#include "gimg/engine/context.h"
#include "gimg/engine/resources.h"

#include "allocator.h"
#include "pipelines.h"
#include "vk_dispatch.h"

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>

namespace gimg::detail {

struct Device {
    GlobalFns global{};
    InstanceFns ifn{};
    DeviceFns fn{};

    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t queue_family = 0;
    bool owns_instance = false;
    bool owns_device = false;

    bool validation = false;
    bool debug_utils = false;  // object names available
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    std::atomic<std::uint64_t> validation_messages{0};

    DeviceInfo info;
    VkPhysicalDeviceMemoryProperties memory_properties{};
    VkPhysicalDeviceLimits limits{};
    VkDeviceSize max_allocation_size = 0;

    Allocator allocator;
    std::unique_ptr<PipelineCache> pipelines;
    VkCommandPool command_pool = VK_NULL_HANDLE;
    VkSampler sampler = VK_NULL_HANDLE;  // nearest, clamp-to-edge: for combined image samplers

    // Every submission signals the next value of one timeline semaphore, so "wait for all of
    // gimg's work" is one wait, and no fence is ever left behind on a borrowed queue.
    VkSemaphore timeline = VK_NULL_HANDLE;
    std::uint64_t timeline_value = 0;
    // Host time spent in wait() on submissions not yet finished (Context::device_wait_seconds).
    std::chrono::steady_clock::duration waited{};
    // How long wait() polls the timeline before it sleeps in vkWaitSemaphores.
    std::chrono::microseconds wait_spin{0};
    void choose_wait_spin(const std::optional<std::uint32_t>& microseconds);

    Device() = default;
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    // Creates the engine's own objects once instance/device/queue are set.
    void init_engine_objects(const std::optional<std::uint64_t>& keep_freed_memory);

    void set_name(VkObjectType type, std::uint64_t handle, const std::string& name) const;

    Buffer create_buffer(const BufferDesc& desc, MemoryUsage usage);
    // A buffer whose memory the caller provides (a graph's aliasing block), or unbound (memory
    // left empty) so the caller can query its requirements first.
    Buffer create_buffer_unbound(const BufferDesc& desc);
    Image create_image(const ImageDesc& desc);
    // Linear images start PREINITIALIZED, so that what the host writes survives the first transition.
    Image create_image_unbound(const ImageDesc& desc, VkImageUsageFlags usage,
                               VkImageTiling tiling = VK_IMAGE_TILING_OPTIMAL);
    // An image holding what `fill` writes into its bytes, written in place: linear, in device-local
    // memory the host maps, on a CPU or integrated device whose linear images serve every use its
    // optimal ones do. An empty Image where that cannot be.
    Image create_image_in_place(const ImageDesc& desc, const std::function<void(std::span<std::byte>)>& fill);
    void bind(Buffer& buffer, const Allocation& memory);
    void bind(Image& image, const Allocation& memory);
    // A new allocation of `usage` memory for the image, bound (and freed again if binding fails).
    void bind_new_memory(Image& image, const VkMemoryRequirements& requirements, MemoryUsage usage);
    void destroy(Buffer& buffer);
    // For non-coherent host-visible memory (no-ops otherwise).
    void flush_host_writes(const Buffer& buffer) const { allocator.flush(buffer.allocation_, 0); }
    void invalidate_for_host(const Buffer& buffer) const { allocator.invalidate(buffer.allocation_, 0); }
    void destroy(Image& image);

    VkCommandBuffer allocate_command_buffer();
    // Submits and returns the timeline value that marks its completion. An open upload batch's
    // commands are submitted first, so what they upload is there for `cmd`.
    std::uint64_t submit(VkCommandBuffer cmd);
    void wait(std::uint64_t value);
    bool finished(std::uint64_t value);
    // Waits for every submission, the pending upload batch submitted first.
    void wait_idle() {
        flush_batch();
        wait(timeline_value);
    }
    // Records `fill` into a one-time command buffer, submits it and waits.
    void run_now(const std::function<void(VkCommandBuffer)>& fill);

    // Uploads batched into one submission (Context::batch_uploads). While a batch is open, run_soon
    // records `fill` into the batch's command buffer and keeps `staging` alive until flush_batch
    // submits the batch and waits; otherwise it runs now.
    void begin_batch() { ++batch_depth; }
    void end_batch();
    void run_soon(const std::function<void(VkCommandBuffer)>& fill, Buffer&& staging);
    void flush_batch();
    int batch_depth = 0;
    VkCommandBuffer batch_cmd = VK_NULL_HANDLE;
    std::vector<Buffer> batch_staging;

    // Barrier from a resource's tracked state to `next`, recorded into cmd; updates the state.
    void transition(VkCommandBuffer cmd, Buffer& buffer, Access next);
    void transition(VkCommandBuffer cmd, Image& image, Access next);
};

}  // namespace gimg::detail

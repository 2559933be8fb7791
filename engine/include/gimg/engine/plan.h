#pragma once
// A compiled render graph: passes in execution order with the barriers derived for them, the
// culled passes, the physical resources behind the transients, and the means to execute.

#include "gimg/engine/handles.h"
#include "gimg/engine/resources.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gimg {

namespace detail {
struct PlanData;
}

struct BarrierInfo {
    std::string resource;  // the resource's debug name
    bool image = false;
    VkPipelineStageFlags2 src_stages = 0;
    VkAccessFlags2 src_access = 0;
    VkPipelineStageFlags2 dst_stages = 0;
    VkAccessFlags2 dst_access = 0;
    VkImageLayout old_layout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImageLayout new_layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

struct PlannedPass {
    std::string name;
    bool raster = false;
    std::uint32_t iterations = 1;              // of its loop; 1 outside loops
    std::vector<BarrierInfo> barriers;         // before its first iteration
    std::vector<BarrierInfo> repeat_barriers;  // before each later iteration
};

struct PassTiming {
    std::string name;
    double gpu_ms = 0.0;  // summed over the pass's iterations
    std::uint32_t iterations = 0;
};

struct ExecuteOptions {
    bool wait = true;         // block until the GPU has finished
    bool timestamps = false;  // time every pass (read with Plan::timings())
};

struct MemoryPlacement {
    std::uint32_t block = 0;  // which aliasing block (buffers and images use separate blocks)
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;
};

class Plan {
public:
    Plan(std::unique_ptr<detail::PlanData> data);
    ~Plan();
    Plan(Plan&&) noexcept;
    Plan& operator=(Plan&&) noexcept;

    // Inspection (no device needed). Barriers are those of the first execution, from the
    // imported resources' last accesses at compile time.
    const std::vector<PlannedPass>& passes() const;
    const std::vector<std::string>& culled_passes() const;
    const std::vector<BarrierInfo>& final_barriers() const;  // towards the exports' next accesses
    const PlannedPass& pass(const std::string& name) const;
    // Index of the physical resource behind a transient; nullopt for imports and unused ones.
    std::optional<std::uint32_t> physical_resource(BufferHandle buffer) const;
    std::optional<std::uint32_t> physical_resource(ImageHandle image) const;
    std::uint32_t physical_resource_count() const;
    // Where a transient's physical resource lives in the plan's aliasing blocks.
    std::optional<MemoryPlacement> placement(BufferHandle buffer) const;
    std::optional<MemoryPlacement> placement(ImageHandle image) const;
    VkDeviceSize transient_memory_bytes() const;  // all aliasing blocks together
    std::string describe() const;                 // the whole plan as text, barriers included

    // Records, submits and (by default) waits. The first call creates the transient resources.
    void execute(const ExecuteOptions& options = {});
    // Records into the caller's command buffer instead of submitting (embedding); the caller
    // submits it on the context's queue. Call collect_timings() after it completed.
    void record(VkCommandBuffer command_buffer, bool timestamps = false);
    void wait();
    // Whether the last execution has finished, without waiting (true before the first): poll it
    // instead of wait() to overlap host work with the GPU's.
    bool finished();
    // Per-pass GPU times of the last timed execution (waits for it).
    const std::vector<PassTiming>& timings();
    double total_gpu_ms();

    // The physical objects of imported or exported resources.
    Buffer& buffer(BufferHandle handle);
    Image& image(ImageHandle handle);

private:
    void collect_pending_timings();
    std::unique_ptr<detail::PlanData> data_;
};

}  // namespace gimg

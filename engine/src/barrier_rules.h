#pragma once
// The one rule that turns "this resource was used like that, now it is used like this" into a
// synchronization2 barrier (or none). The render graph's planner, its loop and re-execution
// handling, and the Context's uploads and downloads all go through it.

#include "gimg/engine/access.h"
#include "gimg/engine/format.h"
#include "gimg/engine/sync_state.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <optional>

namespace gimg::detail {

struct Barrier {
    std::uint32_t resource = 0;  // physical resource index (planner) or unused
    bool image = false;
    VkPipelineStageFlags2 src_stages = 0;
    VkAccessFlags2 src_access = 0;
    VkPipelineStageFlags2 dst_stages = 0;
    VkAccessFlags2 dst_access = 0;
    VkImageLayout old_layout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImageLayout new_layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

// The barrier needed before `use` given `state`, and the state after `use`.
//  - read after write: wait for the write and make it visible, unless already visible there;
//  - write after read or write: wait for both (and make earlier writes available);
//  - image layout change: transition, ordered after every earlier access;
//  - discard: the contents do not matter (a transient's first use): images transition from
//    UNDEFINED, but the wait for earlier users of the memory stays.
// Returns nullopt when no barrier is needed.
std::optional<Barrier> advance(SyncState& state, const AccessInfo& use, bool image, bool discard);

// The Vulkan forms: buffers share one global memory barrier (merged), images get their own.
void merge_into(VkMemoryBarrier2& global, const Barrier& barrier);
VkImageMemoryBarrier2 image_barrier(const Barrier& barrier, VkImage image, Format format);

}  // namespace gimg::detail

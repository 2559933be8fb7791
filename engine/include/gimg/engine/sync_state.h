#pragma once
// How a resource was last used, in the detail the barrier derivation needs: the last write and
// every read since. Buffers and images carry one so that a graph (or an upload) synchronises with
// whatever touched them before. Engine-internal; callers use Buffer::last_access().

#include "gimg/engine/access.h"

#include <vulkan/vulkan.h>

namespace gimg::detail {

// The write bits of an access mask: only writes need an availability operation.
VkAccessFlags2 write_bits(VkAccessFlags2 access);

struct SyncState {
    VkPipelineStageFlags2 write_stages = 0;    // stages of the last write (or layout transition)
    VkAccessFlags2 write_access = 0;           // its write bits still to be made available
    VkPipelineStageFlags2 read_stages = 0;     // stages that read since the last write
    VkPipelineStageFlags2 visible_stages = 0;  // the last write is visible to these stages...
    VkAccessFlags2 visible_access = 0;         // ...for these access types
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;

    // The state a single access leaves behind (what an import's "last access" means).
    static SyncState after(Access access);
    bool empty() const { return write_stages == 0 && read_stages == 0; }
    // Union, for memory shared by aliased resources: a barrier from the union covers them all.
    void merge(const SyncState& other);
};

}  // namespace gimg::detail

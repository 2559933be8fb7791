#include "barrier_rules.h"

namespace gimg::detail {

std::optional<Barrier> advance(SyncState& s, const AccessInfo& use, bool image, bool discard) {
    std::optional<Barrier> barrier;
    const VkPipelineStageFlags2 earlier = s.write_stages | s.read_stages;
    auto make = [&](VkPipelineStageFlags2 src_stages, VkAccessFlags2 src_access) {
        Barrier b;
        b.image = image;
        b.src_stages = src_stages;
        b.src_access = src_access;
        b.dst_stages = use.stages;
        b.dst_access = use.access;
        b.old_layout = s.layout;
        b.new_layout = s.layout;
        return b;
    };

    if (image && (discard || use.layout != s.layout)) {
        Barrier b = make(earlier, s.write_access);
        b.old_layout = discard ? VK_IMAGE_LAYOUT_UNDEFINED : s.layout;
        b.new_layout = use.layout;
        barrier = b;
        // The transition is a write that completes before `use`'s stages and is visible to them.
        s.layout = use.layout;
        s.write_stages = use.stages;
        s.write_access = use.writes ? write_bits(use.access) : 0;
        s.read_stages = use.writes ? 0 : use.stages;
        s.visible_stages = use.writes ? 0 : use.stages;
        s.visible_access = use.writes ? 0 : use.access;
        return barrier;
    }

    if (use.writes || discard) {
        // Write-after-write needs the earlier writes made available; write-after-read needs only
        // the execution dependency on the readers.
        if (earlier) barrier = make(earlier, s.write_access);
        if (use.writes) {
            s.write_stages = use.stages;
            s.write_access = write_bits(use.access);
            s.read_stages = 0;
            s.visible_stages = 0;
            s.visible_access = 0;
        } else {
            s = SyncState{};
            s.layout = use.layout;
            s.read_stages = use.stages;
        }
        return barrier;
    }

    if (use.reads) {
        const bool visible = (use.stages & ~s.visible_stages) == 0 && (use.access & ~s.visible_access) == 0;
        if (s.write_stages && !visible) {
            barrier = make(s.write_stages, s.write_access);
            s.visible_stages |= use.stages;
            s.visible_access |= use.access;
        }
        s.read_stages |= use.stages;
    }
    return barrier;
}

void merge_into(VkMemoryBarrier2& global, const Barrier& b) {
    global.srcStageMask |= b.src_stages;
    global.srcAccessMask |= b.src_access;
    global.dstStageMask |= b.dst_stages;
    global.dstAccessMask |= b.dst_access;
}

VkImageMemoryBarrier2 image_barrier(const Barrier& b, VkImage image, Format format) {
    VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    ib.srcStageMask = b.src_stages;
    ib.srcAccessMask = b.src_access;
    ib.dstStageMask = b.dst_stages;
    ib.dstAccessMask = b.dst_access;
    ib.oldLayout = b.old_layout;
    ib.newLayout = b.new_layout;
    ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    ib.image = image;
    ib.subresourceRange = {VkImageAspectFlags(is_depth(format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT),
                           0, 1, 0, 1};
    return ib;
}

}  // namespace gimg::detail

#include "allocator.h"

#include "check.h"

#include <algorithm>

namespace gimg::detail {

void Allocator::init(const DeviceFns* fns, VkDevice device, const VkPhysicalDeviceMemoryProperties& props,
                     VkDeviceSize max_allocation_size, VkDeviceSize non_coherent_atom,
                     const std::optional<std::uint64_t>& keep_budget) {
    non_coherent_atom_ = non_coherent_atom ? non_coherent_atom : 1;
    fns_ = fns;
    device_ = device;
    props_ = props;
    max_allocation_size_ = max_allocation_size;
    // A sixteenth of the largest heap, at most 256 MiB: enough for a mesh's tree and images,
    // little beside what a host engine sharing the device holds.
    VkDeviceSize largest_heap = 0;
    for (std::uint32_t i = 0; i < props.memoryHeapCount; ++i)
        largest_heap = std::max(largest_heap, props.memoryHeaps[i].size);
    keep_budget_ = keep_budget ? *keep_budget : std::min<VkDeviceSize>(VkDeviceSize(256) << 20, largest_heap / 16);
}

std::uint32_t Allocator::choose_type(std::uint32_t type_bits, MemoryUsage usage) const {
    VkMemoryPropertyFlags required = 0, preferred = 0, avoided = 0;
    switch (usage) {
        case MemoryUsage::DeviceLocal:
            preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
            avoided = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
            break;
        case MemoryUsage::Upload:
            required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
            avoided = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
            break;
        case MemoryUsage::Readback:
            required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
            preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
            break;
    }
    // Score: required flags are a must; then prefer `preferred`, then avoid `avoided`.
    int best = -1, best_score = -1;
    for (std::uint32_t i = 0; i < props_.memoryTypeCount; ++i) {
        if (!(type_bits & (1u << i))) continue;
        VkMemoryPropertyFlags flags = props_.memoryTypes[i].propertyFlags;
        if ((flags & required) != required) continue;
        int score = ((flags & preferred) == preferred ? 2 : 0) + ((flags & avoided) ? 0 : 1);
        if (score > best_score) best = int(i), best_score = score;
    }
    if (best < 0)
        throw Error(ErrorKind::Unsupported,
                    "no Vulkan memory type suits the request (type bits " + std::to_string(type_bits) + ")");
    return std::uint32_t(best);
}

Allocation Allocator::allocate(const VkMemoryRequirements& requirements, MemoryUsage usage, const std::string& what) {
    if (max_allocation_size_ && requirements.size > max_allocation_size_)
        throw Error(ErrorKind::OutOfMemory, "'" + what + "' needs " + mib(requirements.size) +
                                                " in one allocation; the device allows at most " +
                                                mib(max_allocation_size_));
    Allocation a;
    a.memory_type = choose_type(requirements.memoryTypeBits, usage);
    // The smallest kept allocation of the type that holds the request with at most an eighth to spare.
    auto reuse = kept_.end();
    for (auto it = kept_.begin(); it != kept_.end(); ++it)
        if (it->memory_type == a.memory_type && it->size >= requirements.size &&
            it->size - requirements.size <= requirements.size / 8 && (reuse == kept_.end() || it->size < reuse->size))
            reuse = it;
    if (reuse != kept_.end()) {
        a = *reuse;
        stats_.kept_bytes -= a.size;
        kept_.erase(reuse);
        count_in(a);
        return a;
    }
    const VkDeviceSize heap = props_.memoryHeaps[props_.memoryTypes[a.memory_type].heapIndex].size;
    if (requirements.size > heap)
        throw Error(ErrorKind::OutOfMemory,
                    "'" + what + "' needs " + mib(requirements.size) + "; the device's memory heap holds " + mib(heap));
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = requirements.size;
    info.memoryTypeIndex = a.memory_type;
    VkResult r = fns_->vkAllocateMemory(device_, &info, nullptr, &a.memory);
    if ((r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY) && !kept_.empty()) {
        release_kept();
        r = fns_->vkAllocateMemory(device_, &info, nullptr, &a.memory);
    }
    if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
        throw Error(ErrorKind::OutOfMemory,
                    std::string(r == VK_ERROR_OUT_OF_DEVICE_MEMORY ? "out of device memory" : "out of host memory") +
                        " allocating " + mib(requirements.size) + " for '" + what + "' (" +
                        mib(stats_.allocated_bytes) + " already allocated by gimg)");
    GIMG_VK_CHECK(r);
    a.size = requirements.size;
    a.owns_memory = true;
    VkMemoryPropertyFlags flags = props_.memoryTypes[a.memory_type].propertyFlags;
    a.coherent = (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
    if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
        r = fns_->vkMapMemory(device_, a.memory, 0, VK_WHOLE_SIZE, 0, &a.mapped);
        if (r != VK_SUCCESS) {
            fns_->vkFreeMemory(device_, a.memory, nullptr);
            GIMG_VK_CHECK(r);
        }
    }
    count_in(a);
    return a;
}

void Allocator::count_in(const Allocation& a) {
    stats_.allocated_bytes += a.size;
    stats_.peak_allocated_bytes = std::max(stats_.peak_allocated_bytes, stats_.allocated_bytes);
    ++stats_.allocations;
}

void Allocator::free(Allocation& allocation) {
    if (allocation.memory != VK_NULL_HANDLE && allocation.owns_memory) {
        stats_.allocated_bytes -= allocation.size;
        --stats_.allocations;
        if (allocation.size <= keep_budget_) {
            kept_.push_back(allocation);
            stats_.kept_bytes += allocation.size;
            while (stats_.kept_bytes > keep_budget_) {
                stats_.kept_bytes -= kept_.front().size;
                fns_->vkFreeMemory(device_, kept_.front().memory, nullptr);
                kept_.erase(kept_.begin());
            }
        } else {
            fns_->vkFreeMemory(device_, allocation.memory, nullptr);  // freeing unmaps
        }
    }
    allocation = {};
}

void Allocator::release_kept() {
    for (const Allocation& a : kept_) fns_->vkFreeMemory(device_, a.memory, nullptr);
    kept_.clear();
    stats_.kept_bytes = 0;
}

namespace {
// Non-coherent ranges must start at a multiple of nonCoherentAtomSize; running to the end of the
// allocation (VK_WHOLE_SIZE) keeps the end valid whatever the requested size.
VkMappedMemoryRange mapped_range(const Allocation& a, VkDeviceSize offset, VkDeviceSize atom) {
    VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
    range.memory = a.memory;
    range.offset = (a.offset + offset) / atom * atom;
    range.size = VK_WHOLE_SIZE;
    return range;
}
}  // namespace

void Allocator::flush(const Allocation& a, VkDeviceSize offset) const {
    if (a.coherent || !a.mapped) return;
    VkMappedMemoryRange range = mapped_range(a, offset, non_coherent_atom_);
    GIMG_VK_CHECK(fns_->vkFlushMappedMemoryRanges(device_, 1, &range));
}

void Allocator::invalidate(const Allocation& a, VkDeviceSize offset) const {
    if (a.coherent || !a.mapped) return;
    VkMappedMemoryRange range = mapped_range(a, offset, non_coherent_atom_);
    GIMG_VK_CHECK(fns_->vkInvalidateMappedMemoryRanges(device_, 1, &range));
}

}  // namespace gimg::detail

#pragma once
// Buffers and images. Each carries the last access made to it (by a graph execution, an upload or
// a download), so importing it into a render graph synchronises with whatever came before without
// the caller stating it. Move-only; destroy them before the Context that made them.

#include "gimg/engine/access.h"
#include "gimg/engine/format.h"
#include "gimg/engine/memory.h"
#include "gimg/engine/sync_state.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <string>

namespace gimg {

namespace detail {
struct Device;
}

struct BufferDesc {
    VkDeviceSize size = 0;
    std::string name;  // shows up in plans, validation messages and errors
};

struct ImageDesc {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    Format format = Format::RGBA8;
    std::string name;
};

class Buffer {
public:
    Buffer() = default;
    ~Buffer();
    Buffer(Buffer&& other) noexcept;
    Buffer& operator=(Buffer&& other) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    // Wraps a buffer the embedding host owns; gimg never destroys it. `last_access` is how the
    // host last used it (gimg synchronises against that on first use).
    static Buffer borrow(VkBuffer buffer, VkDeviceSize size, Access last_access, std::string name);
    // A buffer with no Vulkan object behind it, for inspecting compiled plans without a device.
    static Buffer unbacked(BufferDesc desc, Access last_access = Access::None);

    VkBuffer vk() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    const std::string& name() const { return name_; }
    // Host pointer to the whole buffer when its memory is host-visible, else nullptr. Read it only
    // after the GPU work writing it has finished (Plan::execute waits by default).
    void* mapped() const { return allocation_.mapped; }
    template <class T>
    std::span<T> mapped_as() const {
        return {static_cast<T*>(allocation_.mapped), allocation_.mapped ? size_ / sizeof(T) : 0};
    }
    // The access the caller last made (or the graph, an upload or a download left). Setting it
    // tells gimg what the caller did to the buffer outside gimg.
    Access last_access() const { return last_access_; }
    void set_last_access(Access access);
    detail::SyncState& sync_state() { return sync_; }
    explicit operator bool() const { return buffer_ != VK_NULL_HANDLE || unbacked_; }

private:
    friend struct detail::Device;
    void release();
    detail::Device* device_ = nullptr;  // null for borrowed and unbacked buffers
    VkBuffer buffer_ = VK_NULL_HANDLE;
    Allocation allocation_{};
    VkDeviceSize size_ = 0;
    std::string name_;
    Access last_access_ = Access::None;
    detail::SyncState sync_{};
    bool unbacked_ = false;
};

class Image {
public:
    Image() = default;
    ~Image();
    Image(Image&& other) noexcept;
    Image& operator=(Image&& other) noexcept;
    Image(const Image&) = delete;
    Image& operator=(const Image&) = delete;

    // Wraps an image (and a view of its single mip level and layer) the host owns.
    static Image borrow(VkImage image, VkImageView view, const ImageDesc& desc, Access last_access);
    // An image with no Vulkan object behind it, for inspecting compiled plans without a device.
    static Image unbacked(ImageDesc desc, Access last_access = Access::None);

    VkImage vk() const { return image_; }
    VkImageView view() const { return view_; }
    std::uint32_t width() const { return desc_.width; }
    std::uint32_t height() const { return desc_.height; }
    Format format() const { return desc_.format; }
    const ImageDesc& desc() const { return desc_; }
    const std::string& name() const { return desc_.name; }
    VkDeviceSize byte_size() const { return VkDeviceSize(desc_.width) * desc_.height * bytes_per_pixel(desc_.format); }
    Access last_access() const { return last_access_; }
    void set_last_access(Access access);
    detail::SyncState& sync_state() { return sync_; }
    explicit operator bool() const { return image_ != VK_NULL_HANDLE || unbacked_; }

private:
    friend struct detail::Device;
    void release();
    detail::Device* device_ = nullptr;
    VkImage image_ = VK_NULL_HANDLE;
    VkImageView view_ = VK_NULL_HANDLE;
    Allocation allocation_{};
    ImageDesc desc_{};
    Access last_access_ = Access::None;
    detail::SyncState sync_{};
    bool unbacked_ = false;
};

}  // namespace gimg

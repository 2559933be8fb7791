#include "gimg/engine/resources.h"

#include "device.h"

#include <utility>

namespace gimg {

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& o) noexcept
    : device_(std::exchange(o.device_, nullptr)), buffer_(std::exchange(o.buffer_, VK_NULL_HANDLE)),
      allocation_(std::exchange(o.allocation_, {})), size_(o.size_), name_(std::move(o.name_)),
      last_access_(o.last_access_), sync_(o.sync_), unbacked_(std::exchange(o.unbacked_, false)) {}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        release();
        device_ = std::exchange(o.device_, nullptr);
        buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
        allocation_ = std::exchange(o.allocation_, {});
        size_ = o.size_;
        name_ = std::move(o.name_);
        last_access_ = o.last_access_;
        sync_ = o.sync_;
        unbacked_ = std::exchange(o.unbacked_, false);
    }
    return *this;
}

void Buffer::release() {
    if (device_) device_->destroy(*this);
    device_ = nullptr;
    buffer_ = VK_NULL_HANDLE;
}

Buffer Buffer::borrow(VkBuffer buffer, VkDeviceSize size, Access last_access, std::string name) {
    Buffer b;
    b.buffer_ = buffer;
    b.size_ = size;
    b.name_ = std::move(name);
    b.set_last_access(last_access);
    return b;
}

Buffer Buffer::unbacked(BufferDesc desc, Access last_access) {
    Buffer b;
    b.size_ = desc.size;
    b.name_ = std::move(desc.name);
    b.unbacked_ = true;
    b.set_last_access(last_access);
    return b;
}

void Buffer::set_last_access(Access access) {
    last_access_ = access;
    sync_ = detail::SyncState::after(access);
}

Image::~Image() { release(); }

Image::Image(Image&& o) noexcept
    : device_(std::exchange(o.device_, nullptr)), image_(std::exchange(o.image_, VK_NULL_HANDLE)),
      view_(std::exchange(o.view_, VK_NULL_HANDLE)), allocation_(std::exchange(o.allocation_, {})),
      desc_(std::move(o.desc_)), last_access_(o.last_access_), sync_(o.sync_),
      unbacked_(std::exchange(o.unbacked_, false)) {}

Image& Image::operator=(Image&& o) noexcept {
    if (this != &o) {
        release();
        device_ = std::exchange(o.device_, nullptr);
        image_ = std::exchange(o.image_, VK_NULL_HANDLE);
        view_ = std::exchange(o.view_, VK_NULL_HANDLE);
        allocation_ = std::exchange(o.allocation_, {});
        desc_ = std::move(o.desc_);
        last_access_ = o.last_access_;
        sync_ = o.sync_;
        unbacked_ = std::exchange(o.unbacked_, false);
    }
    return *this;
}

void Image::release() {
    if (device_) device_->destroy(*this);
    device_ = nullptr;
    image_ = VK_NULL_HANDLE;
    view_ = VK_NULL_HANDLE;
}

Image Image::borrow(VkImage image, VkImageView view, const ImageDesc& desc, Access last_access) {
    Image img;
    img.image_ = image;
    img.view_ = view;
    img.desc_ = desc;
    img.set_last_access(last_access);
    return img;
}

Image Image::unbacked(ImageDesc desc, Access last_access) {
    Image img;
    img.desc_ = std::move(desc);
    img.unbacked_ = true;
    img.set_last_access(last_access);
    return img;
}

void Image::set_last_access(Access access) {
    last_access_ = access;
    sync_ = detail::SyncState::after(access);
}

}  // namespace gimg

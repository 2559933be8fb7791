// Context uploads and downloads. Host-visible memory is written and read in place; otherwise the
// data goes through a staging buffer. Either way the resource's tracked last access tells what to
// synchronise with, and is updated, so a graph importing it next waits for exactly this.
#include "gimg/engine/context.h"

#include "check.h"
#include "device.h"

#include <cstring>
#include <utility>

namespace gimg {

namespace {
void check_range(const Buffer& buffer, VkDeviceSize bytes, VkDeviceSize offset, const char* what) {
    if (offset > buffer.size() || bytes > buffer.size() - offset)
        throw Error(ErrorKind::InvalidArgument, std::string(what) + " of " + std::to_string(bytes) +
                                                    " bytes at offset " + std::to_string(offset) + " exceeds buffer '" +
                                                    buffer.name() + "' (" + std::to_string(buffer.size()) + " bytes)");
}
}  // namespace

void Context::upload(Buffer& buffer, const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    check_range(buffer, bytes, offset, "upload");
    if (bytes == 0) return;
    detail::Device& d = *device_;
    if (void* mapped = buffer.mapped()) {
        // The GPU may still be using the buffer: wait for gimg's submitted work, then write in
        // place (an open upload batch writes other buffers: a buffer is mapped or staged, always).
        d.wait(d.timeline_value);
        std::memcpy(static_cast<char*>(mapped) + offset, data, bytes);
        d.flush_host_writes(buffer);
        buffer.set_last_access(Access::HostWrite);
        return;
    }
    Buffer staging = d.create_buffer({bytes, "staging upload"}, MemoryUsage::Upload);
    std::memcpy(staging.mapped(), data, bytes);
    d.flush_host_writes(staging);
    staging.set_last_access(Access::HostWrite);
    d.run_soon(
        [&](VkCommandBuffer cmd) {
            d.transition(cmd, staging, Access::TransferSrc);
            d.transition(cmd, buffer, Access::TransferDst);
            VkBufferCopy region{0, offset, bytes};
            d.fn.vkCmdCopyBuffer(cmd, staging.vk(), buffer.vk(), 1, &region);
        },
        std::move(staging));
}

void Context::download(Buffer& buffer, void* out, VkDeviceSize bytes, VkDeviceSize offset) {
    check_range(buffer, bytes, offset, "download");
    if (bytes == 0) return;
    detail::Device& d = *device_;
    if (buffer.mapped()) {
        if (buffer.last_access() != Access::HostRead)
            d.run_now([&](VkCommandBuffer cmd) { d.transition(cmd, buffer, Access::HostRead); });
        else
            d.wait_idle();
        d.invalidate_for_host(buffer);
        std::memcpy(out, static_cast<const char*>(buffer.mapped()) + offset, bytes);
        return;
    }
    Buffer staging = d.create_buffer({bytes, "staging download"}, MemoryUsage::Readback);
    d.run_now([&](VkCommandBuffer cmd) {
        d.transition(cmd, buffer, Access::TransferSrc);
        d.transition(cmd, staging, Access::TransferDst);
        VkBufferCopy region{offset, 0, bytes};
        d.fn.vkCmdCopyBuffer(cmd, buffer.vk(), staging.vk(), 1, &region);
        d.transition(cmd, staging, Access::HostRead);
    });
    d.invalidate_for_host(staging);
    std::memcpy(out, staging.mapped(), bytes);
}

namespace {
VkBufferImageCopy whole_image(const Image& image) {
    VkBufferImageCopy region{};
    region.imageSubresource = {
        VkImageAspectFlags(is_depth(image.format()) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT), 0, 0, 1};
    region.imageExtent = {image.width(), image.height(), 1};
    return region;
}
}  // namespace

void Context::upload(Image& image, const void* pixels, VkDeviceSize bytes, bool zero_rest) {
    if (zero_rest ? bytes > image.byte_size() : bytes != image.byte_size())
        throw Error(ErrorKind::InvalidArgument, "upload of " + std::to_string(bytes) + " bytes into image '" +
                                                    image.name() + "' of " + std::to_string(image.byte_size()) +
                                                    " bytes");
    upload(image, [&](std::span<std::byte> staging) {
        std::memcpy(staging.data(), pixels, bytes);
        std::memset(staging.data() + bytes, 0, staging.size() - bytes);
    });
}

void Context::upload(Image& image, const std::function<void(std::span<std::byte>)>& fill) {
    detail::Device& d = *device_;
    Buffer staging = d.create_buffer({image.byte_size(), "staging image upload"}, MemoryUsage::Upload);
    fill(std::span<std::byte>(static_cast<std::byte*>(staging.mapped()), image.byte_size()));
    d.flush_host_writes(staging);
    staging.set_last_access(Access::HostWrite);
    d.run_soon(
        [&](VkCommandBuffer cmd) {
            d.transition(cmd, staging, Access::TransferSrc);
            d.transition(cmd, image, Access::TransferDst);
            VkBufferImageCopy region = whole_image(image);
            d.fn.vkCmdCopyBufferToImage(cmd, staging.vk(), image.vk(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                                        &region);
        },
        std::move(staging));
}

Image Context::create_image(const ImageDesc& desc, const std::function<void(std::span<std::byte>)>& fill) {
    if (Image in_place = device_->create_image_in_place(desc, fill)) return in_place;
    Image image = create_image(desc);
    upload(image, fill);
    return image;
}

std::vector<std::byte> Context::download(Image& image) {
    detail::Device& d = *device_;
    const VkDeviceSize bytes = image.byte_size();
    Buffer staging = d.create_buffer({bytes, "staging image download"}, MemoryUsage::Readback);
    d.run_now([&](VkCommandBuffer cmd) {
        d.transition(cmd, image, Access::TransferSrc);
        d.transition(cmd, staging, Access::TransferDst);
        VkBufferImageCopy region = whole_image(image);
        d.fn.vkCmdCopyImageToBuffer(cmd, image.vk(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.vk(), 1, &region);
        d.transition(cmd, staging, Access::HostRead);
    });
    d.invalidate_for_host(staging);
    std::vector<std::byte> out(bytes);
    std::memcpy(out.data(), staging.mapped(), bytes);
    return out;
}

}  // namespace gimg

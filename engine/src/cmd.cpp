#include "gimg/engine/cmd.h"

#include "recorder.h"

#include "gimg/engine/error.h"
#include "gimg/engine/format.h"

#include <string>
#include <vector>

namespace gimg {

using detail::Recorder;

std::uint32_t Cmd::iteration() const { return recorder_->iteration(); }
VkCommandBuffer Cmd::vk() const { return recorder_->command_buffer(); }

void Cmd::dispatch(const Spirv& shader, Groups g, std::initializer_list<Binding> bindings, PushData push) {
    const detail::Pipeline& p = recorder_->compute_pipeline(shader);
    const auto& limits = recorder_->device().limits;
    if (g.x > limits.maxComputeWorkGroupCount[0] || g.y > limits.maxComputeWorkGroupCount[1] ||
        g.z > limits.maxComputeWorkGroupCount[2])
        recorder_->fail(std::string("dispatch of ") + shader.name + " exceeds maxComputeWorkGroupCount");
    recorder_->bind_and_push(p, bindings, push);
    if (g.x && g.y && g.z) recorder_->device().fn.vkCmdDispatch(vk(), g.x, g.y, g.z);
}

void Cmd::dispatch_threads(const Spirv& shader, Groups t, std::initializer_list<Binding> bindings, PushData push) {
    const detail::Pipeline& p = recorder_->compute_pipeline(shader);
    auto groups = [](std::uint32_t n, std::uint32_t size) { return (n + size - 1) / size; };
    dispatch(shader, {groups(t.x, p.local_size[0]), groups(t.y, p.local_size[1]), groups(t.z, p.local_size[2])},
             bindings, push);
}

void Cmd::dispatch_indirect(const Spirv& shader, BufferHandle args, VkDeviceSize offset,
                            std::initializer_list<Binding> bindings, PushData push) {
    const detail::Pipeline& p = recorder_->compute_pipeline(shader);
    VkBuffer buffer = recorder_->buffer(args.id, "indirect arguments");
    recorder_->bind_and_push(p, bindings, push);
    recorder_->device().fn.vkCmdDispatchIndirect(vk(), buffer, offset);
}

void Cmd::draw(const RasterProgram& program, std::uint32_t vertex_count, std::uint32_t instance_count,
               std::initializer_list<Binding> bindings, PushData push) {
    recorder_->bind_and_push(recorder_->graphics_pipeline(program), bindings, push);
    recorder_->device().fn.vkCmdDraw(vk(), vertex_count, instance_count, 0, 0);
}

void Cmd::draw_indexed(const RasterProgram& program, BufferHandle indices, std::uint32_t index_count,
                       std::initializer_list<Binding> bindings, PushData push) {
    VkBuffer buffer = recorder_->buffer(indices.id, "index buffer");
    recorder_->bind_and_push(recorder_->graphics_pipeline(program), bindings, push);
    recorder_->device().fn.vkCmdBindIndexBuffer(vk(), buffer, 0, VK_INDEX_TYPE_UINT32);
    recorder_->device().fn.vkCmdDrawIndexed(vk(), index_count, 1, 0, 0, 0);
}

void Cmd::draw_indirect(const RasterProgram& program, BufferHandle args, VkDeviceSize offset, std::uint32_t draw_count,
                        std::initializer_list<Binding> bindings, PushData push) {
    VkBuffer buffer = recorder_->buffer(args.id, "indirect arguments");
    recorder_->bind_and_push(recorder_->graphics_pipeline(program), bindings, push);
    recorder_->device().fn.vkCmdDrawIndirect(vk(), buffer, offset, draw_count, sizeof(VkDrawIndirectCommand));
}

void Cmd::fill(BufferHandle buffer, std::uint32_t value, VkDeviceSize offset, VkDeviceSize size) {
    recorder_->device().fn.vkCmdFillBuffer(vk(), recorder_->buffer(buffer.id, "fill"), offset, size, value);
}

void Cmd::update(BufferHandle buffer, const void* data, VkDeviceSize size, VkDeviceSize offset) {
    if (size > 65536 || size % 4 != 0 || offset % 4 != 0)
        recorder_->fail("update() takes at most 65536 bytes, in multiples of 4 at a multiple of 4");
    recorder_->device().fn.vkCmdUpdateBuffer(vk(), recorder_->buffer(buffer.id, "update"), offset, size, data);
}

void Cmd::copy(BufferHandle src, BufferHandle dst, VkDeviceSize size, VkDeviceSize src_offset,
               VkDeviceSize dst_offset) {
    VkBuffer s = recorder_->buffer(src.id, "copy source");
    VkBuffer d = recorder_->buffer(dst.id, "copy destination");
    if (size == VK_WHOLE_SIZE) size = recorder_->buffer_size(src.id) - src_offset;
    VkBufferCopy region{src_offset, dst_offset, size};
    recorder_->device().fn.vkCmdCopyBuffer(vk(), s, d, 1, &region);
}

namespace {
VkBufferImageCopy whole(const Image& img) {
    VkBufferImageCopy r{};
    r.imageSubresource = {
        VkImageAspectFlags(is_depth(img.format()) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT), 0, 0, 1};
    r.imageExtent = {img.width(), img.height(), 1};
    return r;
}

// Whole rows, then the last row's first texels (texel arrays are as wide as the image).
std::vector<VkBufferImageCopy> first_texels(const Image& img, std::uint32_t texels) {
    std::vector<VkBufferImageCopy> regions;
    const std::uint32_t width = img.width(), rows = texels / width, rest = texels % width;
    if (rows > img.height() || (rows == img.height() && rest > 0))
        throw Error(ErrorKind::InvalidArgument, img.name() + ": " + std::to_string(texels) + " texels copied from " +
                                                    std::to_string(width) + " x " + std::to_string(img.height()));
    VkBufferImageCopy r = whole(img);
    if (rows > 0) {
        r.imageExtent = {width, rows, 1};
        regions.push_back(r);
    }
    if (rest > 0) {
        r.bufferOffset = VkDeviceSize(rows) * width * bytes_per_pixel(img.format());
        r.imageOffset = {0, std::int32_t(rows), 0};
        r.imageExtent = {rest, 1, 1};
        regions.push_back(r);
    }
    return regions;
}
}  // namespace

void Cmd::copy_texels(ImageHandle src, BufferHandle dst, std::uint32_t texels) {
    Image& img = recorder_->image(src.id, "copy source");
    VkBuffer b = recorder_->buffer(dst.id, "copy destination");
    const std::vector<VkBufferImageCopy> r = first_texels(img, texels);
    if (!r.empty())
        recorder_->device().fn.vkCmdCopyImageToBuffer(vk(), img.vk(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, b,
                                                      std::uint32_t(r.size()), r.data());
}

void Cmd::copy_texels(BufferHandle src, ImageHandle dst, std::uint32_t texels) {
    VkBuffer b = recorder_->buffer(src.id, "copy source");
    Image& img = recorder_->image(dst.id, "copy destination");
    const std::vector<VkBufferImageCopy> r = first_texels(img, texels);
    if (!r.empty())
        recorder_->device().fn.vkCmdCopyBufferToImage(vk(), b, img.vk(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                                      std::uint32_t(r.size()), r.data());
}

void Cmd::copy(ImageHandle src, BufferHandle dst) {
    Image& img = recorder_->image(src.id, "copy source");
    VkBuffer b = recorder_->buffer(dst.id, "copy destination");
    VkBufferImageCopy r = whole(img);
    recorder_->device().fn.vkCmdCopyImageToBuffer(vk(), img.vk(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, b, 1, &r);
}

void Cmd::copy(BufferHandle src, ImageHandle dst) {
    VkBuffer b = recorder_->buffer(src.id, "copy source");
    Image& img = recorder_->image(dst.id, "copy destination");
    VkBufferImageCopy r = whole(img);
    recorder_->device().fn.vkCmdCopyBufferToImage(vk(), b, img.vk(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &r);
}

void Cmd::clear(ImageHandle image, float r, float g, float b, float a) {
    Image& img = recorder_->image(image.id, "clear");
    VkClearColorValue value{};
    value.float32[0] = r;
    value.float32[1] = g;
    value.float32[2] = b;
    value.float32[3] = a;
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    recorder_->device().fn.vkCmdClearColorImage(vk(), img.vk(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value, 1,
                                                &range);
}

}  // namespace gimg

#include "device.h"

#include "barrier_rules.h"
#include "check.h"

#include <cstdio>
#include <utility>

namespace gimg::detail {

Device::~Device() {
    if (device != VK_NULL_HANDLE) {
        // Only gimg's own work: a borrowed queue may carry the host's work, which is not ours
        // to wait for.
        if (timeline != VK_NULL_HANDLE) {
            try {
                wait_idle();
            } catch (const Error& e) {
                std::fprintf(stderr, "gimg: while shutting down: %s\n", e.what());
            }
        }
        if (pipelines) pipelines->clear();
        if (sampler) fn.vkDestroySampler(device, sampler, nullptr);
        if (command_pool) fn.vkDestroyCommandPool(device, command_pool, nullptr);
        if (timeline) fn.vkDestroySemaphore(device, timeline, nullptr);
        allocator.release_kept();
        if (allocator.stats().allocations != 0)
            std::fprintf(stderr,
                         "gimg: %u device allocations outlived their Context (destroy "
                         "buffers, images and plans first)\n",
                         allocator.stats().allocations);
        if (owns_device) fn.vkDestroyDevice(device, nullptr);
    }
    if (messenger != VK_NULL_HANDLE) ifn.vkDestroyDebugUtilsMessengerEXT(instance, messenger, nullptr);
    if (owns_instance && instance != VK_NULL_HANDLE) ifn.vkDestroyInstance(instance, nullptr);
}

void Device::init_engine_objects(const std::optional<std::uint64_t>& keep_freed_memory) {
    allocator.init(&fn, device, memory_properties, max_allocation_size, limits.nonCoherentAtomSize, keep_freed_memory);
    pipelines = std::make_unique<PipelineCache>(*this);

    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = queue_family;
    GIMG_VK_CHECK(fn.vkCreateCommandPool(device, &pool, nullptr, &command_pool));

    VkSemaphoreTypeCreateInfo type{VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO};
    type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
    type.initialValue = 0;
    VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO, &type};
    GIMG_VK_CHECK(fn.vkCreateSemaphore(device, &sem, nullptr, &timeline));
    set_name(VK_OBJECT_TYPE_SEMAPHORE, std::uint64_t(timeline), "gimg timeline");

    VkSamplerCreateInfo s{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    s.magFilter = s.minFilter = VK_FILTER_NEAREST;
    s.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    s.addressModeU = s.addressModeV = s.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    s.maxLod = 0.0f;
    GIMG_VK_CHECK(fn.vkCreateSampler(device, &s, nullptr, &sampler));
}

void Device::set_name(VkObjectType type, std::uint64_t handle, const std::string& name) const {
    if (!debug_utils || !ifn.vkSetDebugUtilsObjectNameEXT || name.empty()) return;
    VkDebugUtilsObjectNameInfoEXT name_info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    name_info.objectType = type;
    name_info.objectHandle = handle;
    name_info.pObjectName = name.c_str();
    ifn.vkSetDebugUtilsObjectNameEXT(device, &name_info);
}

namespace {
// Every buffer can serve every purpose: choosing usage per buffer would buy nothing measurable
// and would make imports fail in passes their creator did not foresee.
constexpr VkBufferUsageFlags kBufferUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                                            VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT |
                                            VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                            VK_BUFFER_USAGE_TRANSFER_DST_BIT;
}  // namespace

Buffer Device::create_buffer_unbound(const BufferDesc& desc) {
    if (desc.size == 0) throw Error(ErrorKind::InvalidArgument, "buffer '" + desc.name + "' has size 0");
    Buffer b;
    b.device_ = this;
    b.size_ = desc.size;
    b.name_ = desc.name;
    VkBufferCreateInfo create{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    create.size = desc.size;
    create.usage = kBufferUsage;
    create.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(fn.vkCreateBuffer(device, &create, nullptr, &b.buffer_),
          "vkCreateBuffer for '" + desc.name + "' (" + mib(desc.size) + ")");
    set_name(VK_OBJECT_TYPE_BUFFER, std::uint64_t(b.buffer_), desc.name);
    return b;
}

Buffer Device::create_buffer(const BufferDesc& desc, MemoryUsage usage) {
    Buffer b = create_buffer_unbound(desc);
    VkMemoryRequirements req;
    fn.vkGetBufferMemoryRequirements(device, b.buffer_, &req);
    Allocation a = allocator.allocate(req, usage, desc.name.empty() ? "buffer" : desc.name);
    try {
        bind(b, a);
    } catch (...) {
        allocator.free(a);
        throw;
    }
    return b;
}

void Device::bind(Buffer& b, const Allocation& a) {
    GIMG_VK_CHECK(fn.vkBindBufferMemory(device, b.buffer_, a.memory, a.offset));
    b.allocation_ = a;
}

namespace {
VkImageUsageFlags default_image_usage(Format format, VkFormatFeatureFlags features) {
    VkImageUsageFlags usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (features & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT) usage |= VK_IMAGE_USAGE_SAMPLED_BIT;
    if (is_depth(format)) {
        if (features & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT)
            usage |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
        return usage;
    }
    if (features & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT) usage |= VK_IMAGE_USAGE_STORAGE_BIT;
    if (features & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT) usage |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    return usage;
}
}  // namespace

Image Device::create_image_unbound(const ImageDesc& desc, VkImageUsageFlags usage, VkImageTiling tiling) {
    if (desc.width == 0 || desc.height == 0)
        throw Error(ErrorKind::InvalidArgument, "image '" + desc.name + "' has a zero size");
    if (desc.width > limits.maxImageDimension2D || desc.height > limits.maxImageDimension2D)
        throw Error(ErrorKind::Unsupported, "image '" + desc.name + "' is " + std::to_string(desc.width) + "x" +
                                                std::to_string(desc.height) + "; the device allows at most " +
                                                std::to_string(limits.maxImageDimension2D) + " per side");
    Image img;
    img.device_ = this;
    img.desc_ = desc;
    VkImageCreateInfo create{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    create.imageType = VK_IMAGE_TYPE_2D;
    create.format = to_vk(desc.format);
    create.extent = {desc.width, desc.height, 1};
    create.mipLevels = 1;
    create.arrayLayers = 1;
    create.samples = VK_SAMPLE_COUNT_1_BIT;
    create.tiling = tiling;
    create.usage = usage;
    create.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    create.initialLayout =
        tiling == VK_IMAGE_TILING_LINEAR ? VK_IMAGE_LAYOUT_PREINITIALIZED : VK_IMAGE_LAYOUT_UNDEFINED;
    check(fn.vkCreateImage(device, &create, nullptr, &img.image_),
          "vkCreateImage for '" + desc.name + "' (" + std::to_string(desc.width) + "x" + std::to_string(desc.height) +
              " " + to_string(desc.format) + ")");
    set_name(VK_OBJECT_TYPE_IMAGE, std::uint64_t(img.image_), desc.name);
    return img;
}

Image Device::create_image(const ImageDesc& desc) {
    VkFormatProperties props;
    ifn.vkGetPhysicalDeviceFormatProperties(physical, to_vk(desc.format), &props);
    VkImageUsageFlags usage = default_image_usage(desc.format, props.optimalTilingFeatures);
    Image img = create_image_unbound(desc, usage);
    VkMemoryRequirements req;
    fn.vkGetImageMemoryRequirements(device, img.image_, &req);
    bind_new_memory(img, req, MemoryUsage::DeviceLocal);
    return img;
}

void Device::bind_new_memory(Image& img, const VkMemoryRequirements& req, MemoryUsage usage) {
    Allocation a = allocator.allocate(req, usage, img.name().empty() ? "image" : img.name());
    try {
        bind(img, a);
    } catch (...) {
        allocator.free(a);
        throw;
    }
}

Image Device::create_image_in_place(const ImageDesc& desc, const std::function<void(std::span<std::byte>)>& fill) {
    if ((info.type != VK_PHYSICAL_DEVICE_TYPE_CPU && info.type != VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU) ||
        is_depth(desc.format) || desc.width == 0 || desc.height == 0)
        return {};
    const VkFormat format = to_vk(desc.format);
    VkFormatProperties props;
    ifn.vkGetPhysicalDeviceFormatProperties(physical, format, &props);
    const VkImageUsageFlags usage = default_image_usage(desc.format, props.optimalTilingFeatures);
    if (default_image_usage(desc.format, props.linearTilingFeatures) != usage) return {};
    VkImageFormatProperties limits_linear;
    if (ifn.vkGetPhysicalDeviceImageFormatProperties(physical, format, VK_IMAGE_TYPE_2D, VK_IMAGE_TILING_LINEAR, usage,
                                                     0, &limits_linear) != VK_SUCCESS ||
        desc.width > limits_linear.maxExtent.width || desc.height > limits_linear.maxExtent.height)
        return {};
    Image img = create_image_unbound(desc, usage, VK_IMAGE_TILING_LINEAR);
    // Rows packed as the fill writes them, in memory both the device's own and mapped.
    const VkImageSubresource whole{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0};
    VkSubresourceLayout layout;
    fn.vkGetImageSubresourceLayout(device, img.image_, &whole, &layout);
    if (layout.rowPitch != VkDeviceSize(desc.width) * bytes_per_pixel(desc.format) || layout.size < img.byte_size())
        return {};
    VkMemoryRequirements req;
    fn.vkGetImageMemoryRequirements(device, img.image_, &req);
    constexpr VkMemoryPropertyFlags kShared = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT |
                                              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                              VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    std::uint32_t shared_types = 0;
    for (std::uint32_t i = 0; i < memory_properties.memoryTypeCount; ++i)
        if ((memory_properties.memoryTypes[i].propertyFlags & kShared) == kShared) shared_types |= 1u << i;
    req.memoryTypeBits &= shared_types;
    if (req.memoryTypeBits == 0) return {};
    bind_new_memory(img, req, MemoryUsage::Upload);
    fill(std::span<std::byte>(static_cast<std::byte*>(img.allocation_.mapped) + layout.offset, img.byte_size()));
    // A host write the first use waits for, from the preinitialized layout that keeps it.
    img.sync_.layout = VK_IMAGE_LAYOUT_PREINITIALIZED;
    img.sync_.write_stages = VK_PIPELINE_STAGE_2_HOST_BIT;
    img.sync_.write_access = VK_ACCESS_2_HOST_WRITE_BIT;
    img.last_access_ = Access::HostWrite;
    return img;
}

void Device::bind(Image& img, const Allocation& a) {
    GIMG_VK_CHECK(fn.vkBindImageMemory(device, img.image_, a.memory, a.offset));
    img.allocation_ = a;
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = img.image_;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = to_vk(img.desc_.format);
    view.subresourceRange = {
        VkImageAspectFlags(is_depth(img.desc_.format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT), 0, 1, 0,
        1};
    GIMG_VK_CHECK(fn.vkCreateImageView(device, &view, nullptr, &img.view_));
}

void Device::destroy(Buffer& b) {
    if (b.buffer_) fn.vkDestroyBuffer(device, b.buffer_, nullptr);
    allocator.free(b.allocation_);
    b.buffer_ = VK_NULL_HANDLE;
}

void Device::destroy(Image& img) {
    if (img.view_) fn.vkDestroyImageView(device, img.view_, nullptr);
    if (img.image_) fn.vkDestroyImage(device, img.image_, nullptr);
    allocator.free(img.allocation_);
    img.view_ = VK_NULL_HANDLE;
    img.image_ = VK_NULL_HANDLE;
}

VkCommandBuffer Device::allocate_command_buffer() {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = command_pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd;
    GIMG_VK_CHECK(fn.vkAllocateCommandBuffers(device, &alloc, &cmd));
    return cmd;
}

std::uint64_t Device::submit(VkCommandBuffer cmd) {
    flush_batch();
    const std::uint64_t value = timeline_value + 1;
    VkCommandBufferSubmitInfo cb{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cb.commandBuffer = cmd;
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = timeline;
    signal.value = value;
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cb;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signal;
    GIMG_VK_CHECK(fn.vkQueueSubmit2(queue, 1, &submit, VK_NULL_HANDLE));
    timeline_value = value;
    return value;
}

void Device::choose_wait_spin(const std::optional<std::uint32_t>& microseconds) {
    // On a CPU device the device's work runs on the host's cores, which a polling thread would take.
    const bool cpu_device = info.type == VK_PHYSICAL_DEVICE_TYPE_CPU;
    wait_spin = std::chrono::microseconds(microseconds.value_or(cpu_device ? 0u : 1000u));
}

void Device::wait(std::uint64_t value) {
    if (value == 0 || finished(value)) return;
    const auto start = std::chrono::steady_clock::now();
    // Polled first: a thread asleep in vkWaitSemaphores can wake a scheduler tick after the signal.
    const auto until = start + wait_spin;
    bool done = false;
    while (!done && std::chrono::steady_clock::now() < until) done = finished(value);
    if (!done) {
        VkSemaphoreWaitInfo wait_info{VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO};
        wait_info.semaphoreCount = 1;
        wait_info.pSemaphores = &timeline;
        wait_info.pValues = &value;
        GIMG_VK_CHECK(fn.vkWaitSemaphores(device, &wait_info, UINT64_MAX));
    }
    waited += std::chrono::steady_clock::now() - start;
}

bool Device::finished(std::uint64_t value) {
    std::uint64_t done = 0;
    GIMG_VK_CHECK(fn.vkGetSemaphoreCounterValue(device, timeline, &done));
    return done >= value;
}

void Device::run_soon(const std::function<void(VkCommandBuffer)>& fill, Buffer&& staging) {
    if (batch_depth == 0) {
        run_now(fill);
        return;
    }
    if (batch_cmd == VK_NULL_HANDLE) {
        batch_cmd = allocate_command_buffer();
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        GIMG_VK_CHECK(fn.vkBeginCommandBuffer(batch_cmd, &begin));
    }
    fill(batch_cmd);
    batch_staging.push_back(std::move(staging));
}

void Device::flush_batch() {
    if (batch_cmd == VK_NULL_HANDLE) return;
    VkCommandBuffer cmd = std::exchange(batch_cmd, VK_NULL_HANDLE);
    struct Release {
        Device* d;
        VkCommandBuffer c;
        ~Release() {
            d->fn.vkFreeCommandBuffers(d->device, d->command_pool, 1, &c);
            d->batch_staging.clear();
        }
    } release{this, cmd};
    GIMG_VK_CHECK(fn.vkEndCommandBuffer(cmd));
    wait(submit(cmd));
}

void Device::end_batch() {
    if (batch_depth > 0 && --batch_depth == 0) flush_batch();
}

void Device::run_now(const std::function<void(VkCommandBuffer)>& fill) {
    VkCommandBuffer cmd = allocate_command_buffer();
    struct Free {
        Device* d;
        VkCommandBuffer c;
        ~Free() { d->fn.vkFreeCommandBuffers(d->device, d->command_pool, 1, &c); }
    } free_later{this, cmd};
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    GIMG_VK_CHECK(fn.vkBeginCommandBuffer(cmd, &begin));
    fill(cmd);
    GIMG_VK_CHECK(fn.vkEndCommandBuffer(cmd));
    wait(submit(cmd));
}

namespace {
void record_barrier(const DeviceFns& fn, VkCommandBuffer cmd, const Barrier& b, VkImage image, Format format) {
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    VkMemoryBarrier2 global{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    VkImageMemoryBarrier2 img{};
    if (image == VK_NULL_HANDLE) {
        merge_into(global, b);
        dep.memoryBarrierCount = 1;
        dep.pMemoryBarriers = &global;
    } else {
        img = image_barrier(b, image, format);
        dep.imageMemoryBarrierCount = 1;
        dep.pImageMemoryBarriers = &img;
    }
    fn.vkCmdPipelineBarrier2(cmd, &dep);
}
}  // namespace

void Device::transition(VkCommandBuffer cmd, Buffer& buffer, Access next) {
    if (auto b = advance(buffer.sync_state(), access_info(next), false, false))
        record_barrier(fn, cmd, *b, VK_NULL_HANDLE, Format::R32F);
    buffer.last_access_ = next;
}

void Device::transition(VkCommandBuffer cmd, Image& image, Access next) {
    if (auto b = advance(image.sync_state(), access_info(next), true, false))
        record_barrier(fn, cmd, *b, image.vk(), image.format());
    image.last_access_ = next;
}

}  // namespace gimg::detail

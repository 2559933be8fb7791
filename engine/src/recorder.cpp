#include "recorder.h"

#include "check.h"

#include <algorithm>

namespace gimg::detail {

void Recorder::fail(const std::string& message) const {
    std::string where = pass_ ? "pass '" + plan_.graph.passes[pass_->decl].name + "': " : "";
    throw Error(ErrorKind::InvalidGraph, where + message);
}

const Use* Recorder::declared(std::uint32_t resource) const {
    if (!pass_) return nullptr;
    for (const Use& u : pass_->uses)
        if (u.resource == resource) return &u;
    return nullptr;
}

VkBuffer Recorder::buffer(std::uint32_t resource, const char* use) {
    if (resource >= plan_.graph.resources.size() || plan_.graph.resources[resource].image)
        fail(std::string(use) + ": not a buffer of this graph");
    if (!declared(resource))
        fail(std::string(use) + " of '" + plan_.graph.resources[resource].name() + "', which the pass did not declare");
    PhysicalResource& p = plan_.physicals[plan_.physical_of[resource]];
    return p.imported() ? plan_.graph.resources[resource].imported_buffer->vk() : p.buffer.vk();
}

VkDeviceSize Recorder::buffer_size(std::uint32_t resource) { return plan_.graph.resources[resource].buffer_desc.size; }

Image& Recorder::image(std::uint32_t resource, const char* use) {
    if (resource >= plan_.graph.resources.size() || !plan_.graph.resources[resource].image)
        fail(std::string(use) + ": not an image of this graph");
    if (!declared(resource))
        fail(std::string(use) + " of '" + plan_.graph.resources[resource].name() + "', which the pass did not declare");
    PhysicalResource& p = plan_.physicals[plan_.physical_of[resource]];
    return p.imported() ? *plan_.graph.resources[resource].imported_image : p.image_object;
}

const Pipeline& Recorder::compute_pipeline(const Spirv& shader) { return d_.pipelines->compute(shader); }

const Pipeline& Recorder::graphics_pipeline(const RasterProgram& program) {
    if (!pass_ || !plan_.graph.passes[pass_->decl].raster) fail("draws need a raster pass");
    return d_.pipelines->graphics(program, color_formats_, depth_format_);
}

void Recorder::bind_and_push(const Pipeline& p, std::initializer_list<Binding> bindings, PushData push) {
    d_.fn.vkCmdBindPipeline(cmd_, p.bind_point, p.pipeline);
    const std::size_t expected = p.bindings.empty() ? 0 : p.bindings.back().binding + 1;
    if (bindings.size() != expected)
        fail("program " + p.name + " has bindings 0.." + std::to_string(int(expected) - 1) + " but " +
             std::to_string(bindings.size()) + " resources were given");
    std::vector<VkWriteDescriptorSet> writes;
    std::vector<VkDescriptorBufferInfo> buffer_infos;
    std::vector<VkDescriptorImageInfo> image_infos;
    buffer_infos.reserve(p.bindings.size());
    image_infos.reserve(p.bindings.size());
    for (const ReflectedBinding& rb : p.bindings) {
        const Binding& b = bindings.begin()[rb.binding];
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstBinding = rb.binding;
        w.descriptorCount = 1;
        w.descriptorType = rb.type;
        const bool wants_buffer =
            rb.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER || rb.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        if (wants_buffer != (b.kind == Binding::Kind::Buffer))
            fail("binding " + std::to_string(rb.binding) + " of " + p.name + " needs " +
                 (wants_buffer ? "a buffer" : "an image"));
        if (wants_buffer) {
            VkDescriptorBufferInfo info{buffer(b.resource, "binding"), b.offset, b.size};
            const VkDeviceSize total = buffer_size(b.resource);
            const VkDeviceSize range = b.size == VK_WHOLE_SIZE ? total - std::min(total, b.offset) : b.size;
            const VkDeviceSize limit = rb.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER ? d_.limits.maxStorageBufferRange
                                                                                    : d_.limits.maxUniformBufferRange;
            if (b.offset + range > total || range == 0)
                fail("binding " + std::to_string(rb.binding) + " of " + p.name + " is out of the buffer's range");
            if (range > limit)
                fail("binding " + std::to_string(rb.binding) + " of " + p.name + " spans " + std::to_string(range) +
                     " bytes; the device binds at most " + std::to_string(limit) + ": use Binding::range");
            buffer_infos.push_back(info);
            w.pBufferInfo = &buffer_infos.back();
        } else {
            Image& img = image(b.resource, "binding");
            const Use* u = declared(b.resource);
            VkDescriptorImageInfo info{};
            info.imageView = img.view();
            info.imageLayout = u->info.layout;
            if (rb.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER || rb.type == VK_DESCRIPTOR_TYPE_SAMPLER)
                info.sampler = d_.sampler;
            image_infos.push_back(info);
            w.pImageInfo = &image_infos.back();
        }
        writes.push_back(w);
    }
    if (!writes.empty())
        d_.fn.vkCmdPushDescriptorSetKHR(cmd_, p.bind_point, p.layout, 0, std::uint32_t(writes.size()), writes.data());
    if (push.size == 0 && p.push_constant_bytes == 0) return;
    if (p.push_constant_bytes == 0) fail("program " + p.name + " has no push constants, but the pass pushes some");
    if (push.size < p.push_constant_bytes || push.size > p.push_range_bytes || push.size % 4 != 0)
        fail("program " + p.name + " takes " + std::to_string(p.push_constant_bytes) + " bytes of push constants; " +
             std::to_string(push.size) + " were pushed");
    d_.fn.vkCmdPushConstants(cmd_, p.layout, p.push_stages, 0, push.size, push.data);
}

void Recorder::emit(const std::vector<Barrier>& barriers) {
    if (barriers.empty()) return;
    // Buffers need only one global memory barrier for all of them; images each need their own.
    VkMemoryBarrier2 memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    std::vector<VkImageMemoryBarrier2> images;
    bool any_buffer = false;
    for (const Barrier& b : barriers) {
        PhysicalResource& p = plan_.physicals[b.resource];
        if (!b.image) {
            any_buffer = true;
            merge_into(memory, b);
            continue;
        }
        const Image& img = p.imported() ? *plan_.graph.resources[p.import_of].imported_image : p.image_object;
        images.push_back(image_barrier(b, img.vk(), img.format()));
    }
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = any_buffer ? 1 : 0;
    dep.pMemoryBarriers = &memory;
    dep.imageMemoryBarrierCount = std::uint32_t(images.size());
    dep.pImageMemoryBarriers = images.data();
    d_.fn.vkCmdPipelineBarrier2(cmd_, &dep);
}

void Recorder::record_pass(std::uint32_t index, std::uint32_t iteration) {
    pass_ = &plan_.passes[index];
    iteration_ = iteration;
    const PassDecl& decl = plan_.graph.passes[pass_->decl];
    PassScope scope(decl.name);
    Cmd cmd(*this);
    if (!decl.raster) {
        if (decl.record) decl.record(cmd);
        pass_ = nullptr;
        return;
    }
    // Dynamic rendering over the attachments; all must share one size.
    std::vector<VkRenderingAttachmentInfo> colors;
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color_formats_.clear();
    depth_format_ = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{0, 0};
    auto attach = [&](const AttachmentDecl& a, VkRenderingAttachmentInfo& info) {
        Image& img = image(a.resource, "attachment");
        if (extent.width == 0) extent = {img.width(), img.height()};
        if (extent.width != img.width() || extent.height != img.height()) fail("attachments of different sizes");
        info.imageView = img.view();
        info.imageLayout = VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL;
        info.loadOp = a.clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
        info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        if (a.clear) info.clearValue = a.clear->value;
        return img.format();
    };
    for (const AttachmentDecl& a : decl.colors) {
        VkRenderingAttachmentInfo info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        color_formats_.push_back(to_vk(attach(a, info)));
        colors.push_back(info);
    }
    if (decl.depth) depth_format_ = to_vk(attach(*decl.depth, depth));
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = std::uint32_t(colors.size());
    rendering.pColorAttachments = colors.data();
    rendering.pDepthAttachment = decl.depth ? &depth : nullptr;
    d_.fn.vkCmdBeginRendering(cmd_, &rendering);
    VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, extent};
    d_.fn.vkCmdSetViewport(cmd_, 0, 1, &viewport);
    d_.fn.vkCmdSetScissor(cmd_, 0, 1, &scissor);
    if (decl.record) decl.record(cmd);
    d_.fn.vkCmdEndRendering(cmd_);
    pass_ = nullptr;
}

Schedule Recorder::record(bool timestamps) {
    Schedule s = schedule_barriers(plan_, start_states(plan_, plan_.executions == 0));
    const std::uint32_t n = std::uint32_t(plan_.passes.size());

    // One begin/end timestamp pair per recorded pass instance.
    plan_.query_pass.clear();
    if (timestamps) {
        if (d_.info.timestamp_period_ns == 0.0) throw Error(ErrorKind::Unsupported, "the queue has no timestamps");
        std::uint32_t instances = 0;
        for (std::uint32_t i = 0; i < n; ++i)
            instances += plan_.passes[i].loop >= 0 ? plan_.loops[plan_.passes[i].loop].iterations : 1;
        if (2 * instances > plan_.query_capacity) {
            if (plan_.query_pool) d_.fn.vkDestroyQueryPool(d_.device, plan_.query_pool, nullptr);
            plan_.query_pool = VK_NULL_HANDLE;
            VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            info.queryType = VK_QUERY_TYPE_TIMESTAMP;
            info.queryCount = 2 * instances;
            GIMG_VK_CHECK(d_.fn.vkCreateQueryPool(d_.device, &info, nullptr, &plan_.query_pool));
            plan_.query_capacity = info.queryCount;
        }
        d_.fn.vkCmdResetQueryPool(cmd_, plan_.query_pool, 0, 2 * instances);
    }
    auto timed = [&](std::uint32_t i, std::uint32_t iteration) {
        if (!timestamps) return record_pass(i, iteration);
        const std::uint32_t q = 2 * std::uint32_t(plan_.query_pass.size());
        plan_.query_pass.push_back(i);
        // The begin at top of pipe: lavapipe drains its work for any other stage (about 0.15 ms).
        // On lavapipe a compute pass's end is at top of pipe too: lavapipe runs the pass to
        // completion before it reads the next command (its draws, though, wait for a flush).
        const bool completed = d_.info.is_lavapipe && !plan_.graph.passes[plan_.passes[i].decl].raster;
        d_.fn.vkCmdWriteTimestamp2(cmd_, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, plan_.query_pool, q);
        record_pass(i, iteration);
        d_.fn.vkCmdWriteTimestamp2(
            cmd_, completed ? VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT : VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
            plan_.query_pool, q + 1);
    };

    for (std::uint32_t i = 0; i < n;) {
        const int loop = plan_.passes[i].loop;
        if (loop < 0) {
            emit(s.before[i]);
            timed(i, 0);
            ++i;
            continue;
        }
        const CompiledLoop& l = plan_.loops[loop];
        for (std::uint32_t it = 0; it < l.iterations; ++it)
            for (std::uint32_t j = l.first; j < l.end; ++j) {
                emit(it == 0 ? s.before[j] : s.repeat[j]);
                timed(j, it);
            }
        i = l.end;
    }
    emit(s.final_barriers);
    ++plan_.executions;
    return s;
}

}  // namespace gimg::detail

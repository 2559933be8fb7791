#pragma once
// Records one execution of a plan: barriers, dynamic rendering around raster passes, timestamps,
// and the commands pass callbacks issue through Cmd. Engine-internal.

#include "gimg/engine/cmd.h"

#include "device.h"
#include "planner.h"

#include <vector>

namespace gimg::detail {

class Recorder {
public:
    Recorder(PlanData& plan, VkCommandBuffer cmd) : plan_(plan), d_(*plan.device), cmd_(cmd) {}

    // The whole execution into cmd: returns the schedule it used (its end states update imports).
    Schedule record(bool timestamps);

    // Used by Cmd.
    std::uint32_t iteration() const { return iteration_; }
    VkCommandBuffer command_buffer() const { return cmd_; }
    Device& device() { return d_; }
    void bind_and_push(const Pipeline& pipeline, std::initializer_list<Binding> bindings, PushData push);
    const Pipeline& compute_pipeline(const Spirv& shader);
    const Pipeline& graphics_pipeline(const RasterProgram& program);
    VkBuffer buffer(std::uint32_t resource, const char* use);
    Image& image(std::uint32_t resource, const char* use);
    VkDeviceSize buffer_size(std::uint32_t resource);
    [[noreturn]] void fail(const std::string& message) const;

private:
    void emit(const std::vector<Barrier>& barriers);
    void record_pass(std::uint32_t index, std::uint32_t iteration);
    const Use* declared(std::uint32_t resource) const;

    PlanData& plan_;
    Device& d_;
    VkCommandBuffer cmd_;
    const CompiledPass* pass_ = nullptr;
    std::uint32_t iteration_ = 0;
    std::vector<VkFormat> color_formats_;
    VkFormat depth_format_ = VK_FORMAT_UNDEFINED;
};

}  // namespace gimg::detail

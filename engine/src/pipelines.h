#pragma once
// Pipelines made on first use and cached for the Context's life (lavapipe JIT-compiles every
// pipeline, so creating one per dispatch would dominate run time). Layouts come from SPIR-V
// reflection: set 0 is a push-descriptor set, and one push-constant range covers every stage.

#include "gimg/engine/shader.h"

#include "spirv_reflect.h"
#include "vk_dispatch.h"

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

namespace gimg::detail {

struct Pipeline {
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    VkPipelineBindPoint bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
    std::vector<ReflectedBinding> bindings;  // sorted by binding number
    std::uint32_t push_constant_bytes = 0;   // the shader's block size (0: none)
    std::uint32_t push_range_bytes = 0;      // the layout's range (>= block size)
    VkShaderStageFlags push_stages = 0;
    std::array<std::uint32_t, 3> local_size{1, 1, 1};
    std::string name;
};

struct Device;

class PipelineCache {
public:
    explicit PipelineCache(Device& device) : device_(device) {}
    ~PipelineCache();
    PipelineCache(const PipelineCache&) = delete;
    PipelineCache& operator=(const PipelineCache&) = delete;

    // Thread-safe: pipelines of different shaders may be created at once (Context::prepare_compute).
    const Pipeline& compute(const Spirv& shader);
    bool has_compute(const Spirv& shader);
    const Pipeline& graphics(const RasterProgram& program, const std::vector<VkFormat>& color_formats,
                             VkFormat depth_format);
    void clear();

private:
    using GraphicsKey = std::tuple<const std::uint32_t*, const std::uint32_t*, std::vector<VkFormat>, VkFormat, int,
                                   int, bool, bool, bool, int, bool, int, float>;
    Pipeline make_layout(const std::vector<ShaderReflection>& stages, const std::string& name);
    VkShaderModule make_module(const Spirv& shader);
    void destroy_layouts(Pipeline& p);

    Device& device_;
    std::mutex compute_mutex_;  // guards compute_; a pipeline is created outside it
    std::map<const std::uint32_t*, std::unique_ptr<Pipeline>> compute_;
    std::map<GraphicsKey, std::unique_ptr<Pipeline>> graphics_;
};

}  // namespace gimg::detail

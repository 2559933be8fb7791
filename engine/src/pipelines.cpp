#include "pipelines.h"

#include "check.h"
#include "device.h"

#include <algorithm>

namespace gimg::detail {

namespace {
// Push-constant ranges are at least 128 bytes on every Vulkan device; one range of the device's
// size (capped there) lets any pass push up to that without knowing the shader's exact block.
constexpr std::uint32_t kPushRangeCap = 128;

VkPrimitiveTopology to_vk(Topology t) {
    switch (t) {
        case Topology::Lines:
            return VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
        case Topology::Points:
            return VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
        default:
            return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    }
}
VkCullModeFlags to_vk(CullMode c) {
    switch (c) {
        case CullMode::Back:
            return VK_CULL_MODE_BACK_BIT;
        case CullMode::Front:
            return VK_CULL_MODE_FRONT_BIT;
        default:
            return VK_CULL_MODE_NONE;
    }
}
VkCompareOp to_vk(CompareOp c) {
    switch (c) {
        case CompareOp::LessOrEqual:
            return VK_COMPARE_OP_LESS_OR_EQUAL;
        case CompareOp::Greater:
            return VK_COMPARE_OP_GREATER;
        case CompareOp::GreaterOrEqual:
            return VK_COMPARE_OP_GREATER_OR_EQUAL;
        case CompareOp::Always:
            return VK_COMPARE_OP_ALWAYS;
        default:
            return VK_COMPARE_OP_LESS;
    }
}
}  // namespace

PipelineCache::~PipelineCache() { clear(); }

void PipelineCache::destroy_layouts(Pipeline& p) {
    if (p.layout) device_.fn.vkDestroyPipelineLayout(device_.device, p.layout, nullptr);
    if (p.set_layout) device_.fn.vkDestroyDescriptorSetLayout(device_.device, p.set_layout, nullptr);
    p.layout = VK_NULL_HANDLE;
    p.set_layout = VK_NULL_HANDLE;
}

void PipelineCache::clear() {
    auto destroy = [&](Pipeline& p) {
        if (p.pipeline) device_.fn.vkDestroyPipeline(device_.device, p.pipeline, nullptr);
        destroy_layouts(p);
    };
    for (auto& [key, p] : compute_) destroy(*p);
    for (auto& [key, p] : graphics_) destroy(*p);
    compute_.clear();
    graphics_.clear();
}

VkShaderModule PipelineCache::make_module(const Spirv& shader) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = shader.word_count * sizeof(std::uint32_t);
    info.pCode = shader.words;
    VkShaderModule module;
    GIMG_VK_CHECK(device_.fn.vkCreateShaderModule(device_.device, &info, nullptr, &module));
    return module;
}

Pipeline PipelineCache::make_layout(const std::vector<ShaderReflection>& stages, const std::string& name) {
    Pipeline p;
    p.name = name;
    // Merge the stages' bindings: same binding number must mean the same descriptor type.
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (const ShaderReflection& r : stages) {
        for (const ReflectedBinding& b : r.bindings) {
            auto it =
                std::find_if(bindings.begin(), bindings.end(), [&](const auto& x) { return x.binding == b.binding; });
            if (it == bindings.end()) {
                bindings.push_back({b.binding, b.type, 1, VkShaderStageFlags(r.stage), nullptr});
                p.bindings.push_back(b);
            } else if (it->descriptorType != b.type) {
                throw Error(ErrorKind::InvalidArgument, "program " + name + ": binding " + std::to_string(b.binding) +
                                                            " has different types in its stages");
            } else {
                it->stageFlags |= r.stage;
            }
        }
        if (r.push_constant_bytes) {
            p.push_constant_bytes = std::max(p.push_constant_bytes, r.push_constant_bytes);
            p.push_stages |= r.stage;
        }
    }
    std::sort(p.bindings.begin(), p.bindings.end(),
              [](const ReflectedBinding& a, const ReflectedBinding& b) { return a.binding < b.binding; });

    VkPushConstantRange range{};
    p.push_range_bytes = std::min(device_.limits.maxPushConstantsSize, kPushRangeCap);
    if (p.push_constant_bytes > p.push_range_bytes)
        throw Error(ErrorKind::InvalidArgument,
                    "program " + name + " declares " + std::to_string(p.push_constant_bytes) +
                        " bytes of push constants; the limit is " + std::to_string(p.push_range_bytes));
    VkDescriptorSetLayoutCreateInfo set{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    set.bindingCount = std::uint32_t(bindings.size());
    set.pBindings = bindings.data();
    GIMG_VK_CHECK(device_.fn.vkCreateDescriptorSetLayout(device_.device, &set, nullptr, &p.set_layout));

    range.stageFlags = p.push_stages;
    range.size = p.push_range_bytes;
    VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout.setLayoutCount = 1;
    layout.pSetLayouts = &p.set_layout;
    layout.pushConstantRangeCount = p.push_stages ? 1 : 0;
    layout.pPushConstantRanges = &range;
    VkResult result = device_.fn.vkCreatePipelineLayout(device_.device, &layout, nullptr, &p.layout);
    if (result != VK_SUCCESS) destroy_layouts(p);
    GIMG_VK_CHECK(result);
    if (!p.push_stages) p.push_range_bytes = 0;
    return p;
}

bool PipelineCache::has_compute(const Spirv& shader) {
    const std::lock_guard<std::mutex> lock(compute_mutex_);
    return compute_.count(shader.words) != 0;
}

const Pipeline& PipelineCache::compute(const Spirv& shader) {
    {
        const std::lock_guard<std::mutex> lock(compute_mutex_);
        auto it = compute_.find(shader.words);
        if (it != compute_.end()) return *it->second;
    }
    ShaderReflection r = reflect_spirv(shader);
    if (r.stage != VK_SHADER_STAGE_COMPUTE_BIT)
        throw Error(ErrorKind::InvalidArgument, std::string("shader ") + shader.name + " is not a compute shader");
    auto p = std::make_unique<Pipeline>(make_layout({r}, shader.name));
    p->local_size = r.local_size;
    p->bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
    VkShaderModule module = make_module(shader);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                  nullptr,
                  0,
                  VK_SHADER_STAGE_COMPUTE_BIT,
                  module,
                  "main",
                  nullptr};
    info.layout = p->layout;
    VkResult result =
        device_.fn.vkCreateComputePipelines(device_.device, VK_NULL_HANDLE, 1, &info, nullptr, &p->pipeline);
    device_.fn.vkDestroyShaderModule(device_.device, module, nullptr);
    if (result != VK_SUCCESS) destroy_layouts(*p);
    GIMG_VK_CHECK(result);
    device_.set_name(VK_OBJECT_TYPE_PIPELINE, std::uint64_t(p->pipeline), shader.name);
    const std::lock_guard<std::mutex> lock(compute_mutex_);
    auto& slot = compute_[shader.words];
    if (slot) {  // another thread made it meanwhile
        device_.fn.vkDestroyPipeline(device_.device, p->pipeline, nullptr);
        destroy_layouts(*p);
    } else {
        slot = std::move(p);
    }
    return *slot;
}

const Pipeline& PipelineCache::graphics(const RasterProgram& program, const std::vector<VkFormat>& colors,
                                        VkFormat depth) {
    const RasterState& s = program.state;
    GraphicsKey key{program.vertex.words,
                    program.fragment.words,
                    colors,
                    depth,
                    int(s.topology),
                    int(s.cull),
                    s.front_counter_clockwise,
                    s.depth_test,
                    s.depth_write,
                    int(s.depth_compare),
                    s.wireframe,
                    int(s.blend),
                    s.depth_bias};
    auto it = graphics_.find(key);
    if (it != graphics_.end()) return *it->second;

    ShaderReflection vr = reflect_spirv(program.vertex);
    ShaderReflection fr = reflect_spirv(program.fragment);
    if (vr.stage != VK_SHADER_STAGE_VERTEX_BIT || fr.stage != VK_SHADER_STAGE_FRAGMENT_BIT)
        throw Error(ErrorKind::InvalidArgument, std::string("program ") + program.vertex.name + " + " +
                                                    program.fragment.name + " needs a vertex and a fragment shader");
    std::string name = std::string(program.vertex.name) + "+" + program.fragment.name;
    auto p = std::make_unique<Pipeline>(make_layout({vr, fr}, name));
    p->bind_point = VK_PIPELINE_BIND_POINT_GRAPHICS;

    VkShaderModule vm = make_module(program.vertex);
    VkShaderModule fm = make_module(program.fragment);
    VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                                                  VK_SHADER_STAGE_VERTEX_BIT, vm, "main", nullptr},
                                                 {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
                                                  VK_SHADER_STAGE_FRAGMENT_BIT, fm, "main", nullptr}};
    VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = to_vk(s.topology);
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = s.wireframe ? VK_POLYGON_MODE_LINE : VK_POLYGON_MODE_FILL;
    raster.cullMode = to_vk(s.cull);
    raster.frontFace = s.front_counter_clockwise ? VK_FRONT_FACE_COUNTER_CLOCKWISE : VK_FRONT_FACE_CLOCKWISE;
    raster.depthBiasEnable = s.depth_bias != 0.0f;
    raster.depthBiasConstantFactor = s.depth_bias;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth_state{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth_state.depthTestEnable = depth != VK_FORMAT_UNDEFINED && s.depth_test;
    depth_state.depthWriteEnable = depth != VK_FORMAT_UNDEFINED && s.depth_write;
    depth_state.depthCompareOp = to_vk(s.depth_compare);
    std::vector<VkPipelineColorBlendAttachmentState> blends(colors.size());
    for (auto& b : blends) {
        b.colorWriteMask =
            VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
        if (s.blend == Blend::Alpha) {
            b.blendEnable = VK_TRUE;
            b.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
            b.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
            b.colorBlendOp = VK_BLEND_OP_ADD;
            b.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
            b.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
            b.alphaBlendOp = VK_BLEND_OP_ADD;
        }
    }
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = std::uint32_t(blends.size());
    blend.pAttachments = blends.data();
    const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamic_states;
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = std::uint32_t(colors.size());
    rendering.pColorAttachmentFormats = colors.data();
    rendering.depthAttachmentFormat = depth;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rendering};
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertex_input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth_state;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = p->layout;
    VkResult result =
        device_.fn.vkCreateGraphicsPipelines(device_.device, VK_NULL_HANDLE, 1, &info, nullptr, &p->pipeline);
    device_.fn.vkDestroyShaderModule(device_.device, vm, nullptr);
    device_.fn.vkDestroyShaderModule(device_.device, fm, nullptr);
    if (result != VK_SUCCESS) destroy_layouts(*p);
    GIMG_VK_CHECK(result);
    auto& slot = graphics_[key];
    slot = std::move(p);
    device_.set_name(VK_OBJECT_TYPE_PIPELINE, std::uint64_t(slot->pipeline), name);
    return *slot;
}

}  // namespace gimg::detail

#pragma once
// Just enough SPIR-V reflection to build pipeline layouts without hand-written descriptor set
// layouts: the descriptor bindings of set 0, the size of the push-constant block, the stage and
// the compute local size.

#include "gimg/engine/shader.h"

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <vector>

namespace gimg::detail {

struct ReflectedBinding {
    std::uint32_t binding = 0;
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
};

struct ShaderReflection {
    VkShaderStageFlagBits stage = VK_SHADER_STAGE_COMPUTE_BIT;
    std::vector<ReflectedBinding> bindings;  // sorted by binding number
    std::uint32_t push_constant_bytes = 0;   // 0 when the shader has no push-constant block
    std::array<std::uint32_t, 3> local_size{1, 1, 1};
};

// Throws gimg::Error(InvalidArgument) naming the shader for malformed SPIR-V, a descriptor set
// other than 0, or descriptor arrays (gimg binds one resource per binding).
ShaderReflection reflect_spirv(const Spirv& shader);

}  // namespace gimg::detail

#pragma once
// Image formats gimg passes use: float and integer channels for geometry images and reductions,
// 8-bit colour for pictures, 32-bit float depth.

#include <vulkan/vulkan.h>

#include <cstdint>

namespace gimg {

enum class Format : std::uint8_t {
    R32F,
    RG32F,
    RGBA32F,
    R32U,
    RG32U,
    RGBA32U,
    R32I,
    RGBA16F,
    RGBA8,  // UNORM, linear
    D32F,   // depth
};

VkFormat to_vk(Format format);
std::uint32_t bytes_per_pixel(Format format);
bool is_depth(Format format);
const char* to_string(Format format);

}  // namespace gimg

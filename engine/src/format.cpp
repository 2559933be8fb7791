#include "gimg/engine/format.h"

namespace gimg {

VkFormat to_vk(Format format) {
    switch (format) {
        case Format::R32F:
            return VK_FORMAT_R32_SFLOAT;
        case Format::RG32F:
            return VK_FORMAT_R32G32_SFLOAT;
        case Format::RGBA32F:
            return VK_FORMAT_R32G32B32A32_SFLOAT;
        case Format::R32U:
            return VK_FORMAT_R32_UINT;
        case Format::RG32U:
            return VK_FORMAT_R32G32_UINT;
        case Format::RGBA32U:
            return VK_FORMAT_R32G32B32A32_UINT;
        case Format::R32I:
            return VK_FORMAT_R32_SINT;
        case Format::RGBA16F:
            return VK_FORMAT_R16G16B16A16_SFLOAT;
        case Format::RGBA8:
            return VK_FORMAT_R8G8B8A8_UNORM;
        case Format::D32F:
            return VK_FORMAT_D32_SFLOAT;
    }
    return VK_FORMAT_UNDEFINED;
}

std::uint32_t bytes_per_pixel(Format format) {
    switch (format) {
        case Format::R32F:
        case Format::R32U:
        case Format::R32I:
        case Format::RGBA8:
        case Format::D32F:
            return 4;
        case Format::RG32F:
        case Format::RG32U:
        case Format::RGBA16F:
            return 8;
        case Format::RGBA32F:
        case Format::RGBA32U:
            return 16;
    }
    return 0;
}

bool is_depth(Format format) { return format == Format::D32F; }

const char* to_string(Format format) {
    switch (format) {
        case Format::R32F:
            return "R32F";
        case Format::RG32F:
            return "RG32F";
        case Format::RGBA32F:
            return "RGBA32F";
        case Format::R32U:
            return "R32U";
        case Format::RG32U:
            return "RG32U";
        case Format::RGBA32U:
            return "RGBA32U";
        case Format::R32I:
            return "R32I";
        case Format::RGBA16F:
            return "RGBA16F";
        case Format::RGBA8:
            return "RGBA8";
        case Format::D32F:
            return "D32F";
    }
    return "?";
}

}  // namespace gimg

#pragma once
// Shaders as the build embeds them (see cmake/GimgShaders.cmake), and the fixed-function state of
// a raster program. Pipelines are created on first use and cached by the Context; their layouts
// come from reflecting the SPIR-V (descriptor set 0 is a push-descriptor set, plus one push
// constant block), so pass code never writes a descriptor set layout.

#include <cstddef>
#include <cstdint>

namespace gimg {

struct Spirv {
    const std::uint32_t* words = nullptr;
    std::size_t word_count = 0;
    const char* name = "";  // for error messages and pipeline debug names
};

// GIMG_SPIRV(gimg_spv_common_scan_comp) -> Spirv over the embedded array of that name.
#define GIMG_SPIRV(array) \
    ::gimg::Spirv { array, sizeof(array) / sizeof(std::uint32_t), #array }

enum class Topology : std::uint8_t { Triangles, Lines, Points };
enum class CullMode : std::uint8_t { None, Back, Front };
enum class CompareOp : std::uint8_t { Less, LessOrEqual, Greater, GreaterOrEqual, Always };
enum class Blend : std::uint8_t { None, Alpha };

struct RasterState {
    Topology topology = Topology::Triangles;
    CullMode cull = CullMode::None;
    bool front_counter_clockwise = true;
    bool depth_test = true;
    bool depth_write = true;
    CompareOp depth_compare = CompareOp::Less;
    bool wireframe = false;  // needs DeviceInfo::fill_mode_non_solid
    Blend blend = Blend::None;
    float depth_bias = 0.0f;  // constant depth bias (e.g. to draw lines over their surface)

    bool operator==(const RasterState&) const = default;
};

struct RasterProgram {
    Spirv vertex;
    Spirv fragment;
    RasterState state;
};

}  // namespace gimg

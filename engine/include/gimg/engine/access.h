#pragma once
// One semantic access enum for everything a pass, an import or an export can do to a resource,
// and the single table that maps it to synchronization2 stages, access masks and image layouts.
// Pass code names only these; the render graph derives every barrier from them.

#include <vulkan/vulkan.h>

#include <cstdint>

namespace gimg {

enum class Access : std::uint8_t {
    None,               // not accessed yet (fresh memory, contents undefined)
    ComputeRead,        // storage buffer/image read in a compute shader
    ComputeWrite,       // storage write in a compute shader
    ComputeReadWrite,   // storage read and write (in place, atomics, ping-pong in a loop)
    ComputeSampled,     // sampled image in a compute shader
    ComputeUniform,     // uniform buffer in a compute shader
    VertexRead,         // storage read in a vertex shader (vertex pulling)
    FragmentRead,       // storage read in a fragment shader
    FragmentWrite,      // storage write in a fragment shader
    FragmentReadWrite,  // storage read/write (atomics) in a fragment shader
    FragmentSampled,    // sampled image in a fragment shader
    GraphicsUniform,    // uniform buffer in vertex and fragment shaders
    IndexBuffer,        // index buffer of an indexed draw
    IndirectArgs,       // indirect draw/dispatch arguments
    ColorAttachment,    // colour attachment of a raster pass (read and write)
    DepthAttachment,    // depth attachment with depth test and write
    TransferSrc,        // copy source
    TransferDst,        // copy/fill/clear destination
    HostRead,           // mapped memory read by the host after the GPU is done
    HostWrite,          // mapped memory written by the host before the GPU starts
};

struct AccessInfo {
    VkPipelineStageFlags2 stages;
    VkAccessFlags2 access;
    VkImageLayout layout;  // for images; buffers ignore it
    bool reads;
    bool writes;
};

// The table. Storage images stay in GENERAL; only attachments, sampling and transfers change
// layout.
AccessInfo access_info(Access access);
const char* to_string(Access access);

}  // namespace gimg

#pragma once
// What a pass's record callback gets: commands on graph handles. Descriptor sets, pipeline
// layouts, attachments, viewports and every barrier are the graph's business; a pass only says
// which program runs on which resources. Bindings are positional: the i-th entry binds to
// `layout(binding = i)` of set 0 (a shader may leave bindings unused by skipping numbers only
// at the end). Using a resource the pass did not declare is an InvalidGraph error.

#include "gimg/engine/handles.h"
#include "gimg/engine/shader.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <initializer_list>
#include <type_traits>

namespace gimg {

namespace detail {
class Recorder;
}

struct Binding {
    enum class Kind : std::uint8_t { Buffer, Image };
    Kind kind;
    std::uint32_t resource;
    VkDeviceSize offset = 0;
    VkDeviceSize size = VK_WHOLE_SIZE;

    Binding(BufferHandle h) : kind(Kind::Buffer), resource(h.id) {}
    Binding(ImageHandle h) : kind(Kind::Image), resource(h.id) {}
    // A sub-range of a buffer (storage buffers above maxStorageBufferRange must be bound so).
    static Binding range(BufferHandle h, VkDeviceSize offset, VkDeviceSize size) {
        Binding b(h);
        b.offset = offset;
        b.size = size;
        return b;
    }
};

// Push-constant bytes: any trivially copyable struct, or nothing.
struct PushData {
    const void* data = nullptr;
    std::uint32_t size = 0;
    PushData() = default;
    template <class T, class = std::enable_if_t<std::is_trivially_copyable_v<T> && !std::is_same_v<T, PushData>>>
    PushData(const T& value) : data(&value), size(sizeof(T)) {}
};

struct Groups {
    std::uint32_t x = 1, y = 1, z = 1;
};

class Cmd {
public:
    // 0-based iteration of the enclosing loop (0 outside loops): pick ping-pong bindings with it.
    std::uint32_t iteration() const;

    void dispatch(const Spirv& shader, Groups groups, std::initializer_list<Binding> bindings, PushData push = {});
    // Enough workgroups to cover `threads` invocations, using the shader's own local size.
    void dispatch_threads(const Spirv& shader, Groups threads, std::initializer_list<Binding> bindings,
                          PushData push = {});
    // Workgroup counts read from a VkDispatchIndirectCommand in `args` at `offset`.
    void dispatch_indirect(const Spirv& shader, BufferHandle args, VkDeviceSize offset,
                           std::initializer_list<Binding> bindings, PushData push = {});

    // Draws inside the raster pass's attachments (vertices are pulled from storage buffers).
    void draw(const RasterProgram& program, std::uint32_t vertex_count, std::uint32_t instance_count,
              std::initializer_list<Binding> bindings, PushData push = {});
    void draw_indexed(const RasterProgram& program, BufferHandle indices, std::uint32_t index_count,
                      std::initializer_list<Binding> bindings, PushData push = {});
    void draw_indirect(const RasterProgram& program, BufferHandle args, VkDeviceSize offset, std::uint32_t draw_count,
                       std::initializer_list<Binding> bindings, PushData push = {});

    void fill(BufferHandle buffer, std::uint32_t value, VkDeviceSize offset = 0, VkDeviceSize size = VK_WHOLE_SIZE);
    // Small host data into a buffer as part of the command stream (at most 65536 bytes).
    void update(BufferHandle buffer, const void* data, VkDeviceSize size, VkDeviceSize offset = 0);
    void copy(BufferHandle src, BufferHandle dst, VkDeviceSize size = VK_WHOLE_SIZE, VkDeviceSize src_offset = 0,
              VkDeviceSize dst_offset = 0);
    void copy(ImageHandle src, BufferHandle dst);
    void copy(BufferHandle src, ImageHandle dst);
    // The first `texels` texels of a texel array (texel_array.h), row by row, from or to the start of
    // a tightly packed buffer.
    void copy_texels(ImageHandle src, BufferHandle dst, std::uint32_t texels);
    void copy_texels(BufferHandle src, ImageHandle dst, std::uint32_t texels);
    void clear(ImageHandle image, float r, float g = 0.0f, float b = 0.0f, float a = 0.0f);

    // The raw command buffer, for commands this class lacks. The graph's barriers still surround
    // the pass; never record a barrier here.
    VkCommandBuffer vk() const;

private:
    friend class detail::Recorder;
    explicit Cmd(detail::Recorder& recorder) : recorder_(&recorder) {}
    detail::Recorder* recorder_;
};

}  // namespace gimg

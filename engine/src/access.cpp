#include "gimg/engine/access.h"

#include "gimg/engine/sync_state.h"

namespace gimg {

namespace {
constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 kVertex = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT;
constexpr VkPipelineStageFlags2 kFragment = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
// ALL_TRANSFER covers copy, fill, update and clear commands alike.
constexpr VkPipelineStageFlags2 kTransfer = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
constexpr VkAccessFlags2 kStorageRead = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr VkAccessFlags2 kStorageWrite = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
constexpr VkImageLayout kGeneral = VK_IMAGE_LAYOUT_GENERAL;
}  // namespace

AccessInfo access_info(Access access) {
    switch (access) {
        case Access::None:
            return {VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_IMAGE_LAYOUT_UNDEFINED, false, false};
        case Access::ComputeRead:
            return {kCompute, kStorageRead, kGeneral, true, false};
        case Access::ComputeWrite:
            return {kCompute, kStorageWrite, kGeneral, false, true};
        case Access::ComputeReadWrite:
            return {kCompute, kStorageRead | kStorageWrite, kGeneral, true, true};
        case Access::ComputeSampled:
            return {kCompute, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, true,
                    false};
        case Access::ComputeUniform:
            return {kCompute, VK_ACCESS_2_UNIFORM_READ_BIT, kGeneral, true, false};
        case Access::VertexRead:
            return {kVertex, kStorageRead, kGeneral, true, false};
        case Access::FragmentRead:
            return {kFragment, kStorageRead, kGeneral, true, false};
        case Access::FragmentWrite:
            return {kFragment, kStorageWrite, kGeneral, false, true};
        case Access::FragmentReadWrite:
            return {kFragment, kStorageRead | kStorageWrite, kGeneral, true, true};
        case Access::FragmentSampled:
            return {kFragment, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, true,
                    false};
        case Access::GraphicsUniform:
            return {kVertex | kFragment, VK_ACCESS_2_UNIFORM_READ_BIT, kGeneral, true, false};
        case Access::IndexBuffer:
            return {VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT, kGeneral, true, false};
        case Access::IndirectArgs:
            return {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, kGeneral, true,
                    false};
        case Access::ColorAttachment:
            return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                    VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                    VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL, true, true};
        case Access::DepthAttachment:
            return {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                    VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL, true, true};
        case Access::TransferSrc:
            return {kTransfer, VK_ACCESS_2_TRANSFER_READ_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, true, false};
        case Access::TransferDst:
            return {kTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, false, true};
        case Access::HostRead:
            return {VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT, kGeneral, true, false};
        case Access::HostWrite:
            return {VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_WRITE_BIT, kGeneral, false, true};
    }
    return {};
}

const char* to_string(Access access) {
    switch (access) {
        case Access::None:
            return "None";
        case Access::ComputeRead:
            return "ComputeRead";
        case Access::ComputeWrite:
            return "ComputeWrite";
        case Access::ComputeReadWrite:
            return "ComputeReadWrite";
        case Access::ComputeSampled:
            return "ComputeSampled";
        case Access::ComputeUniform:
            return "ComputeUniform";
        case Access::VertexRead:
            return "VertexRead";
        case Access::FragmentRead:
            return "FragmentRead";
        case Access::FragmentWrite:
            return "FragmentWrite";
        case Access::FragmentReadWrite:
            return "FragmentReadWrite";
        case Access::FragmentSampled:
            return "FragmentSampled";
        case Access::GraphicsUniform:
            return "GraphicsUniform";
        case Access::IndexBuffer:
            return "IndexBuffer";
        case Access::IndirectArgs:
            return "IndirectArgs";
        case Access::ColorAttachment:
            return "ColorAttachment";
        case Access::DepthAttachment:
            return "DepthAttachment";
        case Access::TransferSrc:
            return "TransferSrc";
        case Access::TransferDst:
            return "TransferDst";
        case Access::HostRead:
            return "HostRead";
        case Access::HostWrite:
            return "HostWrite";
    }
    return "?";
}

namespace detail {

// Write bits of an access mask: only writes need an availability operation.
VkAccessFlags2 write_bits(VkAccessFlags2 access) {
    constexpr VkAccessFlags2 kWrites = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_WRITE_BIT |
                                       VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT |
                                       VK_ACCESS_2_HOST_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
    return access & kWrites;
}

SyncState SyncState::after(Access access) {
    AccessInfo info = access_info(access);
    SyncState s;
    s.layout = info.layout;
    if (info.writes) {
        s.write_stages = info.stages;
        s.write_access = write_bits(info.access);
    } else if (info.reads) {
        s.read_stages = info.stages;
    }
    return s;
}

void SyncState::merge(const SyncState& other) {
    write_stages |= other.write_stages;
    write_access |= other.write_access;
    read_stages |= other.read_stages;
    visible_stages &= other.visible_stages;
    visible_access &= other.visible_access;
}

}  // namespace detail
}  // namespace gimg

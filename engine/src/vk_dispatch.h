#pragma once
// gimg loads every Vulkan entry point into these tables (never calling loader prototypes), so it
// works the same on its own instance and on an embedding host's instance and device, and creates
// nothing global. The lists name exactly the functions the engine uses.

#include <vulkan/vulkan.h>

namespace gimg::detail {

#define GIMG_VK_GLOBAL_FUNCS(X)               \
    X(vkCreateInstance)                       \
    X(vkEnumerateInstanceLayerProperties)     \
    X(vkEnumerateInstanceExtensionProperties) \
    X(vkEnumerateInstanceVersion)

#define GIMG_VK_INSTANCE_FUNCS(X)               \
    X(vkDestroyInstance)                        \
    X(vkEnumeratePhysicalDevices)               \
    X(vkGetPhysicalDeviceProperties2)           \
    X(vkGetPhysicalDeviceFeatures2)             \
    X(vkGetPhysicalDeviceMemoryProperties)      \
    X(vkGetPhysicalDeviceQueueFamilyProperties) \
    X(vkGetPhysicalDeviceFormatProperties)      \
    X(vkGetPhysicalDeviceImageFormatProperties) \
    X(vkEnumerateDeviceExtensionProperties)     \
    X(vkCreateDevice)                           \
    X(vkGetDeviceProcAddr)

#define GIMG_VK_DEBUG_UTILS_FUNCS(X)   \
    X(vkCreateDebugUtilsMessengerEXT)  \
    X(vkDestroyDebugUtilsMessengerEXT) \
    X(vkSetDebugUtilsObjectNameEXT)

#define GIMG_VK_DEVICE_FUNCS(X)       \
    X(vkDestroyDevice)                \
    X(vkGetDeviceQueue)               \
    X(vkDeviceWaitIdle)               \
    X(vkQueueSubmit2)                 \
    X(vkAllocateMemory)               \
    X(vkFreeMemory)                   \
    X(vkMapMemory)                    \
    X(vkUnmapMemory)                  \
    X(vkInvalidateMappedMemoryRanges) \
    X(vkFlushMappedMemoryRanges)      \
    X(vkCreateBuffer)                 \
    X(vkDestroyBuffer)                \
    X(vkGetBufferMemoryRequirements)  \
    X(vkBindBufferMemory)             \
    X(vkCreateImage)                  \
    X(vkDestroyImage)                 \
    X(vkGetImageMemoryRequirements)   \
    X(vkGetImageSubresourceLayout)    \
    X(vkBindImageMemory)              \
    X(vkCreateImageView)              \
    X(vkDestroyImageView)             \
    X(vkCreateSampler)                \
    X(vkDestroySampler)               \
    X(vkCreateShaderModule)           \
    X(vkDestroyShaderModule)          \
    X(vkCreateDescriptorSetLayout)    \
    X(vkDestroyDescriptorSetLayout)   \
    X(vkCreatePipelineLayout)         \
    X(vkDestroyPipelineLayout)        \
    X(vkCreateComputePipelines)       \
    X(vkCreateGraphicsPipelines)      \
    X(vkDestroyPipeline)              \
    X(vkCreateCommandPool)            \
    X(vkDestroyCommandPool)           \
    X(vkAllocateCommandBuffers)       \
    X(vkFreeCommandBuffers)           \
    X(vkResetCommandBuffer)           \
    X(vkBeginCommandBuffer)           \
    X(vkEndCommandBuffer)             \
    X(vkCreateFence)                  \
    X(vkDestroyFence)                 \
    X(vkWaitForFences)                \
    X(vkResetFences)                  \
    X(vkGetFenceStatus)               \
    X(vkCreateSemaphore)              \
    X(vkDestroySemaphore)             \
    X(vkWaitSemaphores)               \
    X(vkGetSemaphoreCounterValue)     \
    X(vkCreateQueryPool)              \
    X(vkDestroyQueryPool)             \
    X(vkGetQueryPoolResults)          \
    X(vkCmdResetQueryPool)            \
    X(vkCmdWriteTimestamp2)           \
    X(vkCmdPipelineBarrier2)          \
    X(vkCmdBindPipeline)              \
    X(vkCmdPushDescriptorSetKHR)      \
    X(vkCmdPushConstants)             \
    X(vkCmdDispatch)                  \
    X(vkCmdDispatchIndirect)          \
    X(vkCmdBeginRendering)            \
    X(vkCmdEndRendering)              \
    X(vkCmdSetViewport)               \
    X(vkCmdSetScissor)                \
    X(vkCmdBindIndexBuffer)           \
    X(vkCmdDraw)                      \
    X(vkCmdDrawIndexed)               \
    X(vkCmdDrawIndirect)              \
    X(vkCmdCopyBuffer)                \
    X(vkCmdCopyBufferToImage)         \
    X(vkCmdCopyImageToBuffer)         \
    X(vkCmdFillBuffer)                \
    X(vkCmdUpdateBuffer)              \
    X(vkCmdClearColorImage)

#define GIMG_VK_DECLARE(name) PFN_##name name = nullptr;

struct GlobalFns {
    PFN_vkGetInstanceProcAddr vkGetInstanceProcAddr = nullptr;
    GIMG_VK_GLOBAL_FUNCS(GIMG_VK_DECLARE)
};

struct InstanceFns {
    GIMG_VK_INSTANCE_FUNCS(GIMG_VK_DECLARE)
    GIMG_VK_DEBUG_UTILS_FUNCS(GIMG_VK_DECLARE)
};

struct DeviceFns {
    GIMG_VK_DEVICE_FUNCS(GIMG_VK_DECLARE)
};

#undef GIMG_VK_DECLARE

// Loads the global functions through get_instance_proc_addr; when it is null, opens the system's
// libvulkan.so.1 (kept open for the process's life). Throws gimg::Error(Unsupported) if absent.
GlobalFns load_global_functions(PFN_vkGetInstanceProcAddr get_instance_proc_addr);
// Instance functions; the debug-utils ones stay null when the extension is not enabled.
InstanceFns load_instance_functions(const GlobalFns& global, VkInstance instance);
// Device functions, through vkGetDeviceProcAddr so calls skip the loader's trampoline. Throws
// gimg::Error(Unsupported) naming the first function the device does not provide.
DeviceFns load_device_functions(const InstanceFns& instance_fns, VkDevice device);

}  // namespace gimg::detail

#include "vk_dispatch.h"

#include "gimg/engine/error.h"

#include <dlfcn.h>

#include <string>

namespace gimg::detail {

namespace {

PFN_vkGetInstanceProcAddr open_system_loader() {
    // The loader stays loaded for the process's life: unloading it while another part of the host
    // process still uses Vulkan would be unsafe, and it costs nothing to keep.
    static void* library = [] {
        void* lib = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
        if (!lib) lib = dlopen("libvulkan.so", RTLD_NOW | RTLD_LOCAL);
        return lib;
    }();
    if (!library)
        throw Error(ErrorKind::Unsupported, "cannot load the Vulkan loader libvulkan.so.1 (install libvulkan1)");
    return reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(library, "vkGetInstanceProcAddr"));
}

}  // namespace

GlobalFns load_global_functions(PFN_vkGetInstanceProcAddr get_instance_proc_addr) {
    GlobalFns fns;
    fns.vkGetInstanceProcAddr = get_instance_proc_addr ? get_instance_proc_addr : open_system_loader();
    if (!fns.vkGetInstanceProcAddr)
        throw Error(ErrorKind::Unsupported, "the Vulkan loader has no vkGetInstanceProcAddr");
#define GIMG_VK_LOAD(name) fns.name = reinterpret_cast<PFN_##name>(fns.vkGetInstanceProcAddr(VK_NULL_HANDLE, #name));
    GIMG_VK_GLOBAL_FUNCS(GIMG_VK_LOAD)
#undef GIMG_VK_LOAD
    if (!fns.vkCreateInstance) throw Error(ErrorKind::Unsupported, "the Vulkan loader provides no vkCreateInstance");
    return fns;
}

InstanceFns load_instance_functions(const GlobalFns& global, VkInstance instance) {
    InstanceFns fns;
#define GIMG_VK_LOAD(name)                                                                  \
    fns.name = reinterpret_cast<PFN_##name>(global.vkGetInstanceProcAddr(instance, #name)); \
    if (!fns.name) throw Error(ErrorKind::Unsupported, "the Vulkan instance provides no " #name);
    GIMG_VK_INSTANCE_FUNCS(GIMG_VK_LOAD)
#undef GIMG_VK_LOAD
#define GIMG_VK_LOAD_OPTIONAL(name) \
    fns.name = reinterpret_cast<PFN_##name>(global.vkGetInstanceProcAddr(instance, #name));
    GIMG_VK_DEBUG_UTILS_FUNCS(GIMG_VK_LOAD_OPTIONAL)
#undef GIMG_VK_LOAD_OPTIONAL
    return fns;
}

DeviceFns load_device_functions(const InstanceFns& instance_fns, VkDevice device) {
    DeviceFns fns;
#define GIMG_VK_LOAD(name)                                                                    \
    fns.name = reinterpret_cast<PFN_##name>(instance_fns.vkGetDeviceProcAddr(device, #name)); \
    if (!fns.name)                                                                            \
        throw Error(ErrorKind::Unsupported,                                                   \
                    "the Vulkan device provides no " #name " (gimg needs Vulkan 1.3 and VK_KHR_push_descriptor)");
    GIMG_VK_DEVICE_FUNCS(GIMG_VK_LOAD)
#undef GIMG_VK_LOAD
    return fns;
}

}  // namespace gimg::detail

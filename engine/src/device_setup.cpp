// Choosing and creating the Vulkan device, and describing it.
#include "device_setup.h"

#include "check.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <vector>

namespace gimg::detail {

namespace {

struct Candidate {
    VkPhysicalDevice physical;
    std::string name;
    VkPhysicalDeviceType type;
    std::string problem;  // why it cannot serve; empty when it can
};

int type_rank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return 3;
        default:
            return 4;
    }
}

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool has_device_extension(const InstanceFns& ifn, VkPhysicalDevice pd, const char* name) {
    std::uint32_t n = 0;
    GIMG_VK_CHECK(ifn.vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr));
    std::vector<VkExtensionProperties> exts(n);
    GIMG_VK_CHECK(ifn.vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data()));
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

// The feature structures gimg queries and enables, chained.
struct FeatureChain {
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    VkPhysicalDeviceVulkan11Features v11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
    explicit FeatureChain(bool with_atomic_float) {
        f2.pNext = &v11;
        v11.pNext = &v12;
        v12.pNext = &v13;
        v13.pNext = with_atomic_float ? &atomic_float : nullptr;
    }
    FeatureChain(const FeatureChain&) = delete;
    FeatureChain& operator=(const FeatureChain&) = delete;
};

std::string missing_requirement(const InstanceFns& ifn, VkPhysicalDevice pd) {
    VkPhysicalDeviceProperties props;
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    ifn.vkGetPhysicalDeviceProperties2(pd, &p2);
    props = p2.properties;
    if (props.apiVersion < VK_API_VERSION_1_3)
        return "supports only Vulkan 1." + std::to_string(VK_API_VERSION_MINOR(props.apiVersion));
    if (!has_device_extension(ifn, pd, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) return "lacks VK_KHR_push_descriptor";
    FeatureChain f(false);
    ifn.vkGetPhysicalDeviceFeatures2(pd, &f.f2);
    if (!f.v13.synchronization2) return "lacks synchronization2";
    if (!f.v13.dynamicRendering) return "lacks dynamicRendering";
    if (!f.v13.maintenance4) return "lacks maintenance4";
    if (!f.v12.timelineSemaphore) return "lacks timelineSemaphore";
    std::uint32_t n = 0;
    ifn.vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    ifn.vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
    for (const auto& q : families)
        if ((q.queueFlags & VK_QUEUE_GRAPHICS_BIT) && (q.queueFlags & VK_QUEUE_COMPUTE_BIT)) return "";
    return "has no queue family with graphics and compute";
}

}  // namespace

namespace {

std::vector<Candidate> candidates_of(Device& d) {
    std::uint32_t n = 0;
    GIMG_VK_CHECK(d.ifn.vkEnumeratePhysicalDevices(d.instance, &n, nullptr));
    std::vector<VkPhysicalDevice> devices(n);
    GIMG_VK_CHECK(d.ifn.vkEnumeratePhysicalDevices(d.instance, &n, devices.data()));
    std::vector<Candidate> candidates;
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        d.ifn.vkGetPhysicalDeviceProperties2(pd, &p2);
        candidates.push_back({pd, p2.properties.deviceName, p2.properties.deviceType, missing_requirement(d.ifn, pd)});
    }
    return candidates;
}

// The best usable candidate the filter admits; nullptr when none. Throws when the filter names
// a device that cannot serve.
const Candidate* best_candidate(const std::vector<Candidate>& candidates, const std::string& filter) {
    const Candidate* best = nullptr;
    for (const auto& c : candidates) {
        if (!filter.empty() && lower(c.name).find(lower(filter)) == std::string::npos) continue;
        if (!filter.empty() && !c.problem.empty())
            throw Error(ErrorKind::Unsupported,
                        "GIMG_DEVICE='" + filter + "' names " + c.name + ", which " + c.problem);
        if (!c.problem.empty()) continue;
        if (!best || type_rank(c.type) < type_rank(best->type)) best = &c;
    }
    return best;
}

}  // namespace

VkPhysicalDevice choose_physical_device(Device& d, const std::string& filter) {
    std::vector<Candidate> candidates = candidates_of(d);
    if (candidates.empty())
        throw Error(ErrorKind::Unsupported,
                    "no Vulkan device found (install mesa-vulkan-drivers for the lavapipe CPU driver)");
    const Candidate* best = best_candidate(candidates, filter);
    if (!best) {
        std::string listing;
        for (const auto& c : candidates)
            listing += "\n  " + c.name + (c.problem.empty() ? "" : " (unusable: " + c.problem + ")");
        if (!filter.empty())
            throw Error(ErrorKind::Unsupported,
                        "GIMG_DEVICE='" + filter + "' matches no Vulkan device; devices:" + listing);
        throw Error(ErrorKind::Unsupported,
                    "no Vulkan device meets gimg's needs (Vulkan 1.3, "
                    "synchronization2, dynamic rendering, push descriptors); "
                    "devices:" +
                        listing);
    }
    return best->physical;
}

std::vector<AvailableDevice> list_physical_devices(Device& d, const std::string& filter) {
    std::vector<Candidate> candidates = candidates_of(d);
    const Candidate* best = nullptr;
    try {
        best = best_candidate(candidates, filter);
    } catch (const Error&) {
        best = nullptr;  // the listing shows why
    }
    std::vector<AvailableDevice> out;
    for (const auto& c : candidates) out.push_back({c.name, c.type, c.problem, &c == best});
    return out;
}

void create_device(Device& d) {
    std::uint32_t n = 0;
    d.ifn.vkGetPhysicalDeviceQueueFamilyProperties(d.physical, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    d.ifn.vkGetPhysicalDeviceQueueFamilyProperties(d.physical, &n, families.data());
    for (std::uint32_t i = 0; i < n; ++i) {
        if ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) && (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) {
            d.queue_family = i;
            break;
        }
    }

    const bool atomic_float_ext = has_device_extension(d.ifn, d.physical, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
    FeatureChain supported(atomic_float_ext);
    d.ifn.vkGetPhysicalDeviceFeatures2(d.physical, &supported.f2);

    // Enable what gimg needs plus the optional features its passes can use when present.
    FeatureChain enable(atomic_float_ext);
    const VkPhysicalDeviceFeatures& s = supported.f2.features;
    VkPhysicalDeviceFeatures& e = enable.f2.features;
    e.shaderFloat64 = s.shaderFloat64;
    e.shaderInt64 = s.shaderInt64;
    e.shaderInt16 = s.shaderInt16;
    e.fragmentStoresAndAtomics = s.fragmentStoresAndAtomics;
    e.vertexPipelineStoresAndAtomics = s.vertexPipelineStoresAndAtomics;
    e.fillModeNonSolid = s.fillModeNonSolid;
    e.independentBlend = s.independentBlend;
    e.shaderStorageImageWriteWithoutFormat = s.shaderStorageImageWriteWithoutFormat;
    e.shaderStorageImageExtendedFormats = s.shaderStorageImageExtendedFormats;
    enable.v11.storageBuffer16BitAccess = supported.v11.storageBuffer16BitAccess;
    enable.v12.timelineSemaphore = VK_TRUE;
    enable.v12.scalarBlockLayout = supported.v12.scalarBlockLayout;
    enable.v12.bufferDeviceAddress = supported.v12.bufferDeviceAddress;
    enable.v12.hostQueryReset = supported.v12.hostQueryReset;
    enable.v12.shaderBufferInt64Atomics = supported.v12.shaderBufferInt64Atomics;
    enable.v12.shaderFloat16 = supported.v12.shaderFloat16;
    enable.v12.shaderInt8 = supported.v12.shaderInt8;
    enable.v12.storageBuffer8BitAccess = supported.v12.storageBuffer8BitAccess;
    enable.v13.synchronization2 = VK_TRUE;
    enable.v13.dynamicRendering = VK_TRUE;
    enable.v13.maintenance4 = VK_TRUE;  // glslang's LocalSizeId needs it
    enable.atomic_float.shaderBufferFloat32Atomics = supported.atomic_float.shaderBufferFloat32Atomics;
    enable.atomic_float.shaderBufferFloat32AtomicAdd = supported.atomic_float.shaderBufferFloat32AtomicAdd;

    std::vector<const char*> extensions{VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    if (atomic_float_ext) extensions.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueFamilyIndex = d.queue_family;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.pNext = &enable.f2;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    info.enabledExtensionCount = std::uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    GIMG_VK_CHECK(d.ifn.vkCreateDevice(d.physical, &info, nullptr, &d.device));
    d.owns_device = true;
    d.fn = load_device_functions(d.ifn, d.device);
    d.fn.vkGetDeviceQueue(d.device, d.queue_family, 0, &d.queue);
    describe_device(d, &enable.f2);
}

void describe_device(Device& d, const VkPhysicalDeviceFeatures2* enabled) {
    VkPhysicalDeviceVulkan11Properties p11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES};
    VkPhysicalDeviceVulkan12Properties p12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_PROPERTIES, &p11};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &p12};
    d.ifn.vkGetPhysicalDeviceProperties2(d.physical, &p2);
    d.ifn.vkGetPhysicalDeviceMemoryProperties(d.physical, &d.memory_properties);
    d.limits = p2.properties.limits;

    DeviceInfo& info = d.info;
    info.name = p2.properties.deviceName;
    info.type = p2.properties.deviceType;
    info.api_version = p2.properties.apiVersion;
    info.driver_id = p12.driverID;
    info.driver = std::string(p12.driverName) + " " + p12.driverInfo;
    info.is_lavapipe = p12.driverID == VK_DRIVER_ID_MESA_LLVMPIPE;
    info.max_storage_buffer_range = d.limits.maxStorageBufferRange;
    info.max_push_constants_size = d.limits.maxPushConstantsSize;
    info.subgroup_size = p11.subgroupSize;
    info.subgroup_arithmetic = (p11.subgroupSupportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                               (p11.subgroupSupportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT);
    info.subgroup_vote = (p11.subgroupSupportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                         (p11.subgroupSupportedOperations & VK_SUBGROUP_FEATURE_VOTE_BIT);
    info.max_image_dimension_2d = d.limits.maxImageDimension2D;
    d.max_allocation_size = p11.maxMemoryAllocationSize;

    std::uint32_t n = 0;
    d.ifn.vkGetPhysicalDeviceQueueFamilyProperties(d.physical, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    d.ifn.vkGetPhysicalDeviceQueueFamilyProperties(d.physical, &n, families.data());
    const bool timestamps = d.queue_family < n && families[d.queue_family].timestampValidBits > 0;
    info.timestamp_period_ns = timestamps ? double(d.limits.timestampPeriod) : 0.0;

    // Optional features: what the enabled chain says (our own device), or nothing beyond the
    // requirements when a host lends a device without telling.
    if (enabled) {
        info.shader_float64 = enabled->features.shaderFloat64;
        info.shader_int64 = enabled->features.shaderInt64;
        info.fill_mode_non_solid = enabled->features.fillModeNonSolid;
        info.storage_image_extended_formats = enabled->features.shaderStorageImageExtendedFormats;
        for (auto* s = static_cast<const VkBaseInStructure*>(enabled->pNext); s; s = s->pNext)
            if (s->sType == VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT)
                info.float_atomics = reinterpret_cast<const VkPhysicalDeviceShaderAtomicFloatFeaturesEXT*>(s)
                                         ->shaderBufferFloat32AtomicAdd;
    }
}

}  // namespace gimg::detail

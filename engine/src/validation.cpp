// The Khronos validation layer with synchronization validation, and a real messenger that counts
// what it reports (a messenger chained only into VkInstanceCreateInfo misses device-level
// messages, and a zero count would then pass silently).
#include "check.h"
#include "device_setup.h"

#include <cstdio>
#include <cstring>
#include <vector>

namespace gimg::detail {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
    auto* count = static_cast<std::atomic<std::uint64_t>*>(user);
    count->fetch_add(1);
    std::fprintf(stderr, "gimg: validation %s: %s\n",
                 severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
                 data && data->pMessage ? data->pMessage : "(no message)");
    return VK_FALSE;
}

bool has_layer(const GlobalFns& g, const char* name) {
    std::uint32_t n = 0;
    GIMG_VK_CHECK(g.vkEnumerateInstanceLayerProperties(&n, nullptr));
    std::vector<VkLayerProperties> layers(n);
    GIMG_VK_CHECK(g.vkEnumerateInstanceLayerProperties(&n, layers.data()));
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

bool has_instance_extension(const GlobalFns& g, const char* layer, const char* name) {
    std::uint32_t n = 0;
    GIMG_VK_CHECK(g.vkEnumerateInstanceExtensionProperties(layer, &n, nullptr));
    std::vector<VkExtensionProperties> exts(n);
    GIMG_VK_CHECK(g.vkEnumerateInstanceExtensionProperties(layer, &n, exts.data()));
    for (const auto& e : exts)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

}  // namespace

void create_instance(Device& d, const ContextOptions& options) {
    d.global = load_global_functions(nullptr);
    std::uint32_t version = VK_API_VERSION_1_0;
    if (d.global.vkEnumerateInstanceVersion) GIMG_VK_CHECK(d.global.vkEnumerateInstanceVersion(&version));
    if (version < VK_API_VERSION_1_3)
        throw Error(ErrorKind::Unsupported, "the Vulkan loader supports only Vulkan " +
                                                std::to_string(VK_API_VERSION_MAJOR(version)) + "." +
                                                std::to_string(VK_API_VERSION_MINOR(version)) + "; gimg needs 1.3");

    std::vector<const char*> layers, extensions;
    bool validation = options.validation;
    bool features_ext = false;
    if (validation && !has_layer(d.global, kValidationLayer)) {
        if (options.require_validation)
            throw Error(ErrorKind::Unsupported,
                        "validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                        "(Debian package vulkan-validationlayers)");
        std::fprintf(stderr,
                     "gimg: warning: VK_LAYER_KHRONOS_validation is not installed; "
                     "running without validation\n");
        validation = false;
    }
    if (validation) {
        layers.push_back(kValidationLayer);
        features_ext = has_instance_extension(d.global, kValidationLayer, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
        if (features_ext) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    }
    const bool debug_utils = has_instance_extension(d.global, nullptr, VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (debug_utils && validation) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "gimg";
    app.pEngineName = "gimg";
    app.apiVersion = VK_API_VERSION_1_3;

    // Synchronization validation finds missing barriers; core validation alone does not.
    const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;

    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pNext = (validation && features_ext) ? &features : nullptr;
    info.pApplicationInfo = &app;
    info.enabledLayerCount = std::uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = std::uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    const VkResult created = d.global.vkCreateInstance(&info, nullptr, &d.instance);
    if (created == VK_ERROR_INCOMPATIBLE_DRIVER)  // the loader found no driver at all
        throw Error(ErrorKind::Unsupported,
                    "no Vulkan driver found: install mesa-vulkan-drivers (or your GPU's driver), or check "
                    "VK_DRIVER_FILES");
    GIMG_VK_CHECK(created);
    d.owns_instance = true;
    d.ifn = load_instance_functions(d.global, d.instance);
    d.validation = validation;
    d.debug_utils = validation && debug_utils;

    if (d.debug_utils) {
        VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        m.messageSeverity =
            VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        m.pfnUserCallback = on_validation_message;
        m.pUserData = &d.validation_messages;
        GIMG_VK_CHECK(d.ifn.vkCreateDebugUtilsMessengerEXT(d.instance, &m, nullptr, &d.messenger));
    } else if (validation) {
        throw Error(ErrorKind::Unsupported, "validation needs VK_EXT_debug_utils to count messages");
    }
}

}  // namespace gimg::detail

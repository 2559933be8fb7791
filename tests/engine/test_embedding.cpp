// Embedding: the test plays the host engine. It creates its own instance (with validation and a
// messenger of its own) and device, hands them to gimg, runs gimg's work, destroys gimg and then
// its device. The validation layer reports objects left on a device at vkDestroyDevice, so a
// clean run also shows gimg cleaned up after itself.
#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/primitives.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

// The README's example, verbatim.
#include "embed_example.inc"

namespace {

std::atomic<int> host_messages{0};

VKAPI_ATTR VkBool32 VKAPI_CALL count_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        ++host_messages;
        std::fprintf(stderr, "host validation: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

#define HOST_CHECK(call) ASSERT_EQ((call), VK_SUCCESS) << #call

class HostEngine : public ::testing::Test {
protected:
    void SetUp() override {
        host_messages = 0;
        // Validation as the other GPU tests have it: required, unless GIMG_VALIDATION=0 (the debug
        // messenger itself is the loader's, so it stays).
        const char* env = std::getenv("GIMG_VALIDATION");
        const bool validate = !(env && std::string(env) == "0");
        const char* layer = "VK_LAYER_KHRONOS_validation";
        if (validate) {
            std::uint32_t n = 0;
            vkEnumerateInstanceLayerProperties(&n, nullptr);
            std::vector<VkLayerProperties> layers(n);
            vkEnumerateInstanceLayerProperties(&n, layers.data());
            ASSERT_TRUE(std::any_of(layers.begin(), layers.end(),
                                    [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, layer) == 0; }))
                << "validation was requested but " << layer
                << " is not installed (Debian package vulkan-validationlayers; GIMG_VALIDATION=0 runs without it)";
        }
        const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
        VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
        VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
        features.enabledValidationFeatureCount = 1;
        features.pEnabledValidationFeatures = &sync;
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.apiVersion = VK_API_VERSION_1_3;
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, validate ? &features : nullptr};
        ici.pApplicationInfo = &app;
        ici.enabledLayerCount = validate ? 1 : 0;
        ici.ppEnabledLayerNames = &layer;
        ici.enabledExtensionCount = validate ? 2 : 1;
        ici.ppEnabledExtensionNames = extensions;
        HOST_CHECK(vkCreateInstance(&ici, nullptr, &instance));
        auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
        VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        m.messageSeverity =
            VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
        m.pfnUserCallback = count_message;
        HOST_CHECK(create_messenger(instance, &m, nullptr, &messenger));

        std::uint32_t n = 0;
        vkEnumeratePhysicalDevices(instance, &n, nullptr);
        std::vector<VkPhysicalDevice> devices(n);
        vkEnumeratePhysicalDevices(instance, &n, devices.data());
        for (VkPhysicalDevice d : devices) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(d, &p);
            if (p.apiVersion >= VK_API_VERSION_1_3) {
                physical = d;
                std::printf("host device: %s\n", p.deviceName);
                break;
            }
        }
        ASSERT_NE(physical, VK_NULL_HANDLE) << "no Vulkan 1.3 device";
        std::uint32_t qn = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &qn, nullptr);
        std::vector<VkQueueFamilyProperties> families(qn);
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &qn, families.data());
        while (family < qn && !(families[family].queueFlags & VK_QUEUE_GRAPHICS_BIT)) ++family;

        const float priority = 1.0f;
        VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        q.queueFamilyIndex = family;
        q.queueCount = 1;
        q.pQueuePriorities = &priority;
        // The optional feature the README example's capabilities use, as an engine would enable it.
        VkPhysicalDeviceFeatures supported{};
        vkGetPhysicalDeviceFeatures(physical, &supported);
        required.features2.features.shaderFloat64 = supported.shaderFloat64;
        auto exts = gimg::required_device_extensions();
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, required.chain()};
        dci.queueCreateInfoCount = 1;
        dci.pQueueCreateInfos = &q;
        dci.enabledExtensionCount = std::uint32_t(exts.size());
        dci.ppEnabledExtensionNames = exts.data();
        HOST_CHECK(vkCreateDevice(physical, &dci, nullptr, &device));
        vkGetDeviceQueue(device, family, 0, &queue);
    }

    void TearDown() override {
        if (device) vkDestroyDevice(device, nullptr);  // validation reports any object gimg left behind
        auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
        if (messenger) destroy_messenger(instance, messenger, nullptr);
        if (instance) vkDestroyInstance(instance, nullptr);
        EXPECT_EQ(host_messages.load(), 0) << "validation messages on the host's device";
    }

    gimg::RequiredFeatures required;
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t family = 0;
};

}  // namespace

TEST_F(HostEngine, ReadmeExampleRunsGimgOnTheHostsDevice) {
    if (!required.features2.features.shaderFloat64) GTEST_SKIP() << "the device lacks shaderFloat64";
    // A sphere of radius 0.4 seen from its centre: every pixel hits it, no jump cuts a block, and
    // every rebuilt vertex lies on it.
    const gimg::geo::Mesh sphere = gimg::geo::make_icosphere(0.4, 4);
    const gimg::geo::Mesh rebuilt = rebuild_on_host_device(
        {instance, physical, device, queue, family, vkGetInstanceProcAddr, &required.features2}, sphere);
    EXPECT_EQ(rebuilt.vertex_count(), 256u * 128u);
    EXPECT_EQ(rebuilt.face_count(), 2u * 256u * 127u);
    for (const auto& p : rebuilt.positions) ASSERT_NEAR(glm::length(p), 0.4, 1e-3);
}

TEST_F(HostEngine, PlanRecordsIntoTheHostsCommandBuffer) {
    std::vector<std::uint32_t> values(3000, 2u);
    {
        auto ctx = gimg::Context::borrow({instance, physical, device, queue, family, vkGetInstanceProcAddr});
        gimg::Buffer in = ctx->create_buffer({values.size() * 4, "values"});
        gimg::Buffer out = ctx->create_buffer({values.size() * 4, "sums"});
        ctx->upload(in, values.data(), values.size() * 4);
        gimg::Graph graph(*ctx);
        auto sums = gimg::passes::add_inclusive_scan(graph, graph.import_buffer(in), graph.import_buffer(out),
                                                     std::uint32_t(values.size()));
        graph.export_buffer(sums, gimg::Access::TransferSrc);
        gimg::Plan plan = graph.compile();

        // The host's own command pool, command buffer and fence.
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.queueFamilyIndex = family;
        VkCommandPool pool;
        HOST_CHECK(vkCreateCommandPool(device, &pci, nullptr, &pool));
        VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        cai.commandPool = pool;
        cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        cai.commandBufferCount = 1;
        VkCommandBuffer cmd;
        HOST_CHECK(vkAllocateCommandBuffers(device, &cai, &cmd));
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        HOST_CHECK(vkBeginCommandBuffer(cmd, &begin));
        plan.record(cmd);
        HOST_CHECK(vkEndCommandBuffer(cmd));
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence fence;
        HOST_CHECK(vkCreateFence(device, &fci, nullptr, &fence));
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmd;
        HOST_CHECK(vkQueueSubmit(queue, 1, &submit, fence));
        HOST_CHECK(vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX));
        std::vector<std::uint32_t> result = ctx->download<std::uint32_t>(out);
        for (std::uint32_t i = 0; i < values.size(); ++i) ASSERT_EQ(result[i], 2 * (i + 1));
        vkDestroyFence(device, fence, nullptr);
        vkDestroyCommandPool(device, pool, nullptr);
    }
}

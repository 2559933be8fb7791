#include "check.h"

#include <cstdio>
#include <cstring>

namespace gimg::detail {

namespace {
thread_local const std::string* current_pass = nullptr;

// "fns.vkCreateBuffer(device, ...)" -> "vkCreateBuffer": the call's name without the table prefix
// and the argument list keeps messages short.
std::string call_name(const char* call) {
    std::string s = call;
    if (auto paren = s.find('('); paren != std::string::npos) s.resize(paren);
    if (auto dot = s.rfind('.'); dot != std::string::npos) s.erase(0, dot + 1);
    if (auto arrow = s.rfind("->"); arrow != std::string::npos) s.erase(0, arrow + 2);
    return s;
}
}  // namespace

const char* result_name(VkResult result) {
    switch (result) {
#define GIMG_RESULT_CASE(r) \
    case r:                 \
        return #r;
        GIMG_RESULT_CASE(VK_SUCCESS)
        GIMG_RESULT_CASE(VK_NOT_READY)
        GIMG_RESULT_CASE(VK_TIMEOUT)
        GIMG_RESULT_CASE(VK_EVENT_SET)
        GIMG_RESULT_CASE(VK_EVENT_RESET)
        GIMG_RESULT_CASE(VK_INCOMPLETE)
        GIMG_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        GIMG_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        GIMG_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
        GIMG_RESULT_CASE(VK_ERROR_DEVICE_LOST)
        GIMG_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        GIMG_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        GIMG_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        GIMG_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        GIMG_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        GIMG_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        GIMG_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        GIMG_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
        GIMG_RESULT_CASE(VK_ERROR_UNKNOWN)
        GIMG_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        GIMG_RESULT_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        GIMG_RESULT_CASE(VK_ERROR_FRAGMENTATION)
        GIMG_RESULT_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        GIMG_RESULT_CASE(VK_PIPELINE_COMPILE_REQUIRED)
#undef GIMG_RESULT_CASE
        default:
            return "VkResult(unknown)";
    }
}

namespace {
[[noreturn]] void throw_for(VkResult result, const std::string& what) {
    std::string where;
    if (const std::string* pass = PassScope::current()) where = "pass '" + *pass + "': ";
    const std::string message = where + what;
    switch (result) {
        case VK_ERROR_DEVICE_LOST:
            throw Error(ErrorKind::DeviceLost, message + ": the GPU device was lost");
        case VK_ERROR_OUT_OF_HOST_MEMORY:
        case VK_ERROR_OUT_OF_DEVICE_MEMORY:
        case VK_ERROR_OUT_OF_POOL_MEMORY:
            throw Error(ErrorKind::OutOfMemory, message);
        case VK_ERROR_LAYER_NOT_PRESENT:
        case VK_ERROR_EXTENSION_NOT_PRESENT:
        case VK_ERROR_FEATURE_NOT_PRESENT:
        case VK_ERROR_INCOMPATIBLE_DRIVER:
        case VK_ERROR_FORMAT_NOT_SUPPORTED:
            throw Error(ErrorKind::Unsupported, message);
        default:
            throw Error(ErrorKind::Vulkan, message);
    }
}
}  // namespace

void throw_vk_error(VkResult result, const char* call, const char* file, int line) {
    const char* base = std::strrchr(file, '/');
    throw_for(result, call_name(call) + " failed with " + result_name(result) + " (" + (base ? base + 1 : file) + ":" +
                          std::to_string(line) + ")");
}

void check(VkResult result, const std::string& what) {
    if (result != VK_SUCCESS) throw_for(result, what + " failed with " + result_name(result));
}

std::string mib(VkDeviceSize bytes) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
    return buf;
}

PassScope::PassScope(const std::string& pass_name) : previous_(current_pass) { current_pass = &pass_name; }
PassScope::~PassScope() { current_pass = previous_; }
const std::string* PassScope::current() { return current_pass; }

}  // namespace gimg::detail

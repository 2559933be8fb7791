#pragma once
// VkResult checking. Every Vulkan call that returns a VkResult goes through GIMG_VK_CHECK, which
// turns a failure into gimg::Error naming the call, the result and, inside a render-graph pass,
// the pass (set by PassScope while the pass records).

#include "gimg/engine/error.h"

#include <vulkan/vulkan.h>

#include <string>

namespace gimg::detail {

const char* result_name(VkResult result);

// Throws gimg::Error for any result other than VK_SUCCESS (and the given extra success codes).
[[noreturn]] void throw_vk_error(VkResult result, const char* call, const char* file, int line);

inline void check(VkResult result, const char* call, const char* file, int line) {
    if (result != VK_SUCCESS) throw_vk_error(result, call, file, line);
}

// Like check(), with what was being done in words ("vkCreateBuffer for 'positions' (12.0 MiB)").
void check(VkResult result, const std::string& what);

std::string mib(VkDeviceSize bytes);

// Names the render-graph pass that is recording on this thread, for error messages.
class PassScope {
public:
    explicit PassScope(const std::string& pass_name);
    ~PassScope();
    PassScope(const PassScope&) = delete;
    PassScope& operator=(const PassScope&) = delete;
    static const std::string* current();

private:
    const std::string* previous_;
};

}  // namespace gimg::detail

#define GIMG_VK_CHECK(call) ::gimg::detail::check((call), #call, __FILE__, __LINE__)

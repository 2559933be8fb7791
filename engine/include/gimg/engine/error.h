#pragma once
// gimg's error policy, in one place:
//  - Every Vulkan call is checked; a failure becomes gimg::Error naming the pass (when inside a
//    render-graph pass), the call and the VkResult.
//  - Device loss and out-of-memory get their own kinds so callers can report them plainly.
//  - An invalid render graph (stale handle, undeclared resource, mismatched layouts) is rejected
//    with kind InvalidGraph naming the pass and the resource.
//  - A missing device, layer or feature is kind Unsupported, with a message saying what is missing.

#include <stdexcept>
#include <string>

namespace gimg {

enum class ErrorKind {
    Vulkan,           // a Vulkan call failed with an unexpected result
    DeviceLost,       // VK_ERROR_DEVICE_LOST
    OutOfMemory,      // host or device memory exhausted
    Unsupported,      // no suitable device, missing extension, feature, layer or format
    InvalidGraph,     // the render graph's declarations contradict each other
    InvalidArgument,  // the caller passed something unusable
};

class Error : public std::runtime_error {
public:
    Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
    ErrorKind kind() const { return kind_; }
    // True when the caller's input, not the machine, is at fault.
    bool is_input_error() const { return kind_ == ErrorKind::InvalidArgument; }

private:
    ErrorKind kind_;
};

}  // namespace gimg

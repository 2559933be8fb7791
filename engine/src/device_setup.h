#pragma once
// Creating gimg's own instance and device, or adopting a host's: validation, device choice,
// features. Engine-internal; Context::create and Context::borrow call these.

#include "gimg/engine/context.h"

#include "device.h"

namespace gimg::detail {

// Instance (with the validation layer and a counting messenger when asked), then the device.
void create_instance(Device& d, const ContextOptions& options);
// Picks the device: GIMG_DEVICE-style filter first, else discrete > integrated > virtual > CPU.
VkPhysicalDevice choose_physical_device(Device& d, const std::string& filter);
// Every device with what makes it unusable, and the one choose_physical_device would pick.
std::vector<AvailableDevice> list_physical_devices(Device& d, const std::string& filter);
// Creates the device with the required features and every optional one gimg can use.
void create_device(Device& d);
// Fills d.info and d.limits from the physical device (and the enabled-features chain, if any).
void describe_device(Device& d, const VkPhysicalDeviceFeatures2* enabled_features);

}  // namespace gimg::detail

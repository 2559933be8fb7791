// gimg devices: the Vulkan devices gimg sees, and the one it would use.
#include "commands.h"

#include "gimg/engine/context.h"

#include <cstdio>
#include <cstdlib>

namespace gimg::cli {

namespace {
const char* type_name(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return "CPU";
        default:
            return "other";
    }
}
}  // namespace

void add_devices_command(CLI::App& app, const GlobalOptions&) {
    auto* cmd = app.add_subcommand("devices",
                                   "List the Vulkan devices and the one gimg chooses "
                                   "(GIMG_DEVICE=<part of a name> overrides)");
    cmd->callback([] {
        const char* filter = std::getenv("GIMG_DEVICE");
        auto devices = Context::list_devices(filter ? filter : "");
        if (devices.empty()) std::printf("no Vulkan devices\n");
        for (const auto& d : devices)
            std::printf("%s %s (%s)%s%s\n", d.chosen ? "*" : " ", d.name.c_str(), type_name(d.type),
                        d.problem.empty() ? "" : ": unusable, ", d.problem.c_str());
    });
}

}  // namespace gimg::cli

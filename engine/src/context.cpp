#include "gimg/engine/context.h"

#include "check.h"
#include "device.h"
#include "device_setup.h"
#include "pipelines.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#include <cstdio>
#include <cstdlib>

namespace gimg {

ContextOptions ContextOptions::from_environment() {
    ContextOptions o;
    if (const char* v = std::getenv("GIMG_VALIDATION")) o.validation = std::string(v) == "1";
    if (const char* d = std::getenv("GIMG_DEVICE")) o.device_filter = d;
    if (const char* w = std::getenv("GIMG_WAIT_SPIN_US")) {
        char* end = nullptr;
        const unsigned long us = std::strtoul(w, &end, 10);
        if (end == w || *end != '\0' || us > 1000000)
            throw Error(ErrorKind::InvalidArgument,
                        std::string("GIMG_WAIT_SPIN_US: '") + w + "' is not a number of microseconds up to 1000000");
        o.wait_spin_us = std::uint32_t(us);
    }
    return o;
}

std::string DeviceInfo::summary() const {
    const char* kind = "other";
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            kind = "discrete GPU";
            break;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            kind = "integrated GPU";
            break;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            kind = "virtual GPU";
            break;
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            kind = "CPU";
            break;
        default:
            break;
    }
    return name + " (" + kind + ", driver " + driver + ", Vulkan " + std::to_string(VK_API_VERSION_MAJOR(api_version)) +
           "." + std::to_string(VK_API_VERSION_MINOR(api_version)) + "." +
           std::to_string(VK_API_VERSION_PATCH(api_version)) + ")";
}

namespace {
constexpr const char* kRequiredExtensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
}

std::span<const char* const> required_device_extensions() { return kRequiredExtensions; }

RequiredFeatures::RequiredFeatures() {
    features2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    features2.pNext = &vulkan12;
    vulkan12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
    vulkan12.pNext = &vulkan13;
    vulkan12.timelineSemaphore = VK_TRUE;
    vulkan13.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES;
    vulkan13.synchronization2 = VK_TRUE;
    vulkan13.dynamicRendering = VK_TRUE;
    vulkan13.maintenance4 = VK_TRUE;
}

Context::Context(std::unique_ptr<detail::Device> device) : device_(std::move(device)) {}
Context::~Context() = default;

std::unique_ptr<Context> Context::create(const ContextOptions& options) {
    auto d = std::make_unique<detail::Device>();
    detail::create_instance(*d, options);
    d->physical = detail::choose_physical_device(*d, options.device_filter);
    detail::create_device(*d);
    d->init_engine_objects(options.keep_freed_memory);
    d->choose_wait_spin(options.wait_spin_us);
    if (options.verbose)
        std::fprintf(stderr, "gimg: device: %s%s\n", d->info.summary().c_str(),
                     d->validation ? " [validation on]" : "");
    return std::unique_ptr<Context>(new Context(std::move(d)));
}

std::unique_ptr<Context> Context::borrow(const ExternalDevice& ext, const ContextOptions& options) {
    if (!ext.instance || !ext.physical_device || !ext.device || !ext.queue || !ext.get_instance_proc_addr)
        throw Error(ErrorKind::InvalidArgument,
                    "Context::borrow needs instance, physical device, device, queue and "
                    "vkGetInstanceProcAddr");
    auto d = std::make_unique<detail::Device>();
    d->global = detail::load_global_functions(ext.get_instance_proc_addr);
    d->instance = ext.instance;
    d->physical = ext.physical_device;
    d->device = ext.device;
    d->queue = ext.queue;
    d->queue_family = ext.queue_family;
    d->ifn = detail::load_instance_functions(d->global, d->instance);
    d->fn = detail::load_device_functions(d->ifn, d->device);
    detail::describe_device(*d, ext.enabled_features);
    if (d->info.api_version < VK_API_VERSION_1_3)
        throw Error(ErrorKind::Unsupported, "the borrowed device " + d->info.name + " is not Vulkan 1.3");
    d->init_engine_objects(options.keep_freed_memory);
    d->choose_wait_spin(options.wait_spin_us);
    if (options.verbose) std::fprintf(stderr, "gimg: device (borrowed): %s\n", d->info.summary().c_str());
    return std::unique_ptr<Context>(new Context(std::move(d)));
}

std::vector<AvailableDevice> Context::list_devices(const std::string& device_filter) {
    detail::Device d;
    detail::create_instance(d, ContextOptions{});
    return detail::list_physical_devices(d, device_filter);
}

const DeviceInfo& Context::device_info() const { return device_->info; }
bool Context::validation_enabled() const { return device_->validation; }
std::uint64_t Context::validation_message_count() const { return device_->validation_messages.load(); }

Buffer Context::create_buffer(const BufferDesc& desc, MemoryUsage usage) { return device_->create_buffer(desc, usage); }

Image Context::create_image(const ImageDesc& desc) { return device_->create_image(desc); }

void Context::wait_idle() { device_->wait_idle(); }

void Context::prepare_compute(std::initializer_list<Spirv> shaders) {
    std::vector<Spirv> missing;
    for (const Spirv& s : shaders)
        if (!device_->pipelines->has_compute(s)) missing.push_back(s);
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto work = [&] {
        for (std::size_t i = next++; i < missing.size(); i = next++) {
            try {
                device_->pipelines->compute(missing[i]);
            } catch (...) {
                const std::lock_guard<std::mutex> lock(failure_mutex);
                if (!failure) failure = std::current_exception();
            }
        }
    };
    const std::size_t threads = std::min<std::size_t>(missing.size(), std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> helpers;
    for (std::size_t t = 1; t < threads; ++t) helpers.emplace_back(work);
    work();
    for (std::thread& h : helpers) h.join();
    if (failure) std::rethrow_exception(failure);
}

void Context::batch_uploads(const std::function<void()>& uploads) {
    device_->begin_batch();
    try {
        uploads();
    } catch (...) {
        // The recorded copies are still valid: submit them, so that no resource's tracked state
        // claims a copy that never ran, and report the first error.
        try {
            device_->end_batch();
        } catch (const Error&) {}
        throw;
    }
    device_->end_batch();
}

std::uint64_t Context::submission_count() const { return device_->timeline_value; }

double Context::device_wait_seconds() const { return std::chrono::duration<double>(device_->waited).count(); }

std::uint32_t Context::wait_spin_us() const { return std::uint32_t(device_->wait_spin.count()); }

void Context::set_wait_spin_us(std::uint32_t microseconds) {
    device_->wait_spin = std::chrono::microseconds(microseconds);
}

MemoryStats Context::memory_stats() const { return device_->allocator.stats(); }

void Context::release_kept_memory() { device_->allocator.release_kept(); }

}  // namespace gimg

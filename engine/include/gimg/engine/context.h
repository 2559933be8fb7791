#pragma once
// The Vulkan context: instance, device and queue gimg works on, either its own (headless, no
// window system) or borrowed from an embedding host. One queue. Not thread-safe: use a Context
// and everything made from it from one thread at a time.

#include "gimg/engine/memory.h"
#include "gimg/engine/resources.h"
#include "gimg/engine/shader.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace gimg {

namespace detail {
struct Device;
}

struct ContextOptions {
    bool validation = false;          // Khronos validation with synchronization validation
    bool require_validation = false;  // fail instead of warning when the layer is missing
    std::string device_filter;        // case-insensitive part of the device name
    bool verbose = false;             // print the chosen device to stderr
    // Freed device memory kept for reuse, at most (docs/engine.md, "Resources"); unset: a
    // sixteenth of the largest memory heap, at most 256 MiB. 0 keeps none.
    std::optional<std::uint64_t> keep_freed_memory;
    // How long a wait for the device polls its progress before the host thread sleeps, in
    // microseconds (docs/engine.md, "Round trips"): a sleeping thread may wake a scheduler tick
    // after the work is done. Unset: 0 on a CPU device (lavapipe, whose work needs the host's
    // cores), 1000 on a GPU.
    std::optional<std::uint32_t> wait_spin_us;

    // GIMG_VALIDATION=1 turns validation on; GIMG_DEVICE=<part of a name> picks the device;
    // GIMG_WAIT_SPIN_US=<microseconds> sets wait_spin_us.
    static ContextOptions from_environment();
};

struct DeviceInfo {
    std::string name;    // VkPhysicalDeviceProperties::deviceName
    std::string driver;  // driver name and info, e.g. "llvmpipe: Mesa 22.3.6 (LLVM 15)"
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    VkDriverId driver_id = VkDriverId(0);
    std::uint32_t api_version = 0;
    bool is_lavapipe = false;  // Mesa's CPU driver (driverID MESA_LLVMPIPE)
    bool shader_float64 = false;
    bool shader_int64 = false;
    bool float_atomics = false;  // shaderBufferFloat32AtomicAdd
    bool fill_mode_non_solid = false;
    bool storage_image_extended_formats = false;  // storage images of RG32F, RG32UI and the like
    VkDeviceSize max_storage_buffer_range = 0;
    std::uint32_t max_push_constants_size = 0;
    std::uint32_t subgroup_size = 0;
    bool subgroup_arithmetic = false;  // compute shaders have subgroupAdd and the like
    bool subgroup_vote = false;        // compute shaders have subgroupAll and subgroupAny
    std::uint32_t max_image_dimension_2d = 0;
    double timestamp_period_ns = 0.0;  // 0 when the queue has no timestamps
    std::string summary() const;       // one line: name, type, driver, API version
};

// Handles an embedding host owns and lends to gimg. The device must have been created with
// Vulkan 1.3 and what required_device_extensions() and RequiredFeatures name. gimg creates its own
// command pool, fences and pipelines on it and destroys them again; it never destroys the
// host's objects and never waits on work that is not its own.
struct ExternalDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical_device = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;  // the host must not use it from another thread meanwhile
    std::uint32_t queue_family = 0;
    PFN_vkGetInstanceProcAddr get_instance_proc_addr = nullptr;  // the host's loader
    // Optional: the VkPhysicalDeviceFeatures2 chain the device was created with, so gimg knows
    // which optional features (float64, float atomics, ...) it may use.
    const VkPhysicalDeviceFeatures2* enabled_features = nullptr;
};

// A Vulkan device as gimg sees it when choosing one.
struct AvailableDevice {
    std::string name;
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    std::string problem;  // why gimg cannot use it; empty when it can
    bool chosen = false;  // what Context::create would pick with the same filter
};

// Device extensions gimg needs on a borrowed device.
std::span<const char* const> required_device_extensions();

// Features gimg needs, ready to chain into VkDeviceCreateInfo::pNext:
//   RequiredFeatures f; create_info.pNext = f.chain();
struct RequiredFeatures {
    VkPhysicalDeviceFeatures2 features2{};
    VkPhysicalDeviceVulkan12Features vulkan12{};
    VkPhysicalDeviceVulkan13Features vulkan13{};
    RequiredFeatures();
    RequiredFeatures(const RequiredFeatures&) = delete;
    RequiredFeatures& operator=(const RequiredFeatures&) = delete;
    const void* chain() const { return &features2; }
};

class Context {
public:
    // A headless context on the best device: discrete > integrated > virtual > CPU, or the one
    // options.device_filter names. Throws gimg::Error(Unsupported) when none qualifies.
    static std::unique_ptr<Context> create(const ContextOptions& options = ContextOptions::from_environment());
    // A context on the host's device and queue (see ExternalDevice).
    static std::unique_ptr<Context> borrow(const ExternalDevice& external, const ContextOptions& options = {});
    // Every device the Vulkan loader offers, and which one create() would choose.
    static std::vector<AvailableDevice> list_devices(const std::string& device_filter = "");
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    const DeviceInfo& device_info() const;
    bool validation_enabled() const;
    // Warnings and errors the validation layer reported so far (0 when validation is off).
    std::uint64_t validation_message_count() const;

    Buffer create_buffer(const BufferDesc& desc, MemoryUsage usage = MemoryUsage::DeviceLocal);
    Image create_image(const ImageDesc& desc);
    // An image holding what `fill` writes into its bytes (tightly packed rows of
    // bytes_per_pixel(format), top to bottom): written in place where the device reads images the
    // host wrote into its memory (lavapipe and integrated GPUs: linear images in memory both share),
    // else uploaded through staging as upload(image, fill) does.
    Image create_image(const ImageDesc& desc, const std::function<void(std::span<std::byte>)>& fill);

    // Copies host data into a buffer (mapped memcpy or staging copy) and waits. Synchronises with
    // earlier GPU use of the buffer through its last access.
    void upload(Buffer& buffer, const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
    template <class T>
    void upload(Buffer& buffer, std::span<const T> data, VkDeviceSize offset = 0) {
        upload(buffer, data.data(), data.size_bytes(), offset);
    }
    // Copies buffer contents to the host once all GPU work gimg submitted has finished.
    void download(Buffer& buffer, void* out, VkDeviceSize bytes, VkDeviceSize offset = 0);
    template <class T>
    std::vector<T> download(Buffer& buffer) {
        std::vector<T> out(buffer.size() / sizeof(T));
        download(buffer, out.data(), out.size() * sizeof(T));
        return out;
    }
    // Whole-image transfers, tightly packed rows of bytes_per_pixel(format). With zero_rest, `bytes`
    // may be fewer than the image holds: the rest is zeros.
    void upload(Image& image, const void* pixels, VkDeviceSize bytes, bool zero_rest = false);
    // The same with every byte of the image written by `fill` straight into the staging memory,
    // which spares a large array its host copy.
    void upload(Image& image, const std::function<void(std::span<std::byte>)>& fill);
    std::vector<std::byte> download(Image& image);

    // Runs `uploads` with every upload that goes through staging (create_image with a fill, and
    // upload, on a device whose memory the host cannot map) recorded into one submission, made and
    // waited for when `uploads` returns, or before anything else is submitted meanwhile. A real GPU
    // takes its time for each submission it waits for, so several uploads cost one; on lavapipe and
    // integrated GPUs, which need no staging, nothing changes. What `uploads` creates can be used
    // once it returns. Batches may nest; the outermost one submits. A plan recorded into the host's
    // own command buffer (Plan::record) inside a batch is submitted by the host, so only after the
    // batch has returned.
    void batch_uploads(const std::function<void()>& uploads);
    // Queue submissions gimg made on this context so far: plans, transfers, batches.
    std::uint64_t submission_count() const;
    // Seconds the host spent so far waiting for this context's submissions to finish (in plans'
    // waits, transfers and wait_idle): with submission_count, what tells a run bound by round trips
    // or by the device's work from one bound by the host's.
    double device_wait_seconds() const;
    // ContextOptions::wait_spin_us as chosen for this device, and a change of it (for measuring).
    std::uint32_t wait_spin_us() const;
    void set_wait_spin_us(std::uint32_t microseconds);

    // Creates the compute pipelines of `shaders` that this context has not made yet, on up to one
    // thread per core, and returns when all exist. A pass otherwise makes its pipeline the first
    // time it is recorded, one after another (lavapipe: up to about 20 ms for a large shader).
    void prepare_compute(std::initializer_list<Spirv> shaders);

    // Waits for every submission gimg made on this context.
    void wait_idle();
    MemoryStats memory_stats() const;
    // Frees the device memory kept for reuse (memory_stats().kept_bytes), e.g. for a host that
    // needs it back.
    void release_kept_memory();

    detail::Device& device() { return *device_; }

private:
    explicit Context(std::unique_ptr<detail::Device> device);
    std::unique_ptr<detail::Device> device_;
};

}  // namespace gimg

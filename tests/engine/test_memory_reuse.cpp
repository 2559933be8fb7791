// Freed device memory is kept for the next request of about its size, and the stats tell live
// memory from kept memory.
#include "gimg/engine/context.h"

#include "gpu_test.h"

using namespace gimg;

class MemoryReuse : public gimg::test::GpuTest {};

namespace {
// A size no other test frees, so the block kept here is the only one that fits it.
constexpr VkDeviceSize kOddSize = 3'333'333;
}  // namespace

TEST_F(MemoryReuse, AFreedBlockServesTheNextRequestOfItsSize) {
    const MemoryStats before = ctx().memory_stats();
    void* first_memory = nullptr;
    {
        Buffer b = ctx().create_buffer({kOddSize, "first"}, MemoryUsage::Upload);
        ASSERT_NE(b.mapped(), nullptr);
        first_memory = b.mapped();
        EXPECT_EQ(ctx().memory_stats().allocations, before.allocations + 1);
        EXPECT_GE(ctx().memory_stats().allocated_bytes, before.allocated_bytes + kOddSize);
    }
    // Freed: no longer live, but kept.
    const MemoryStats freed = ctx().memory_stats();
    EXPECT_EQ(freed.allocations, before.allocations);
    EXPECT_EQ(freed.allocated_bytes, before.allocated_bytes);
    EXPECT_GE(freed.kept_bytes, before.kept_bytes + kOddSize);

    // A request far smaller than the kept block gets memory of its own...
    Buffer small = ctx().create_buffer({kOddSize / 4, "small"}, MemoryUsage::Upload);
    EXPECT_NE(small.mapped(), first_memory);
    // ...and the next request of the block's size gets the block, mapped where it was.
    const std::uint64_t kept = ctx().memory_stats().kept_bytes;
    Buffer second = ctx().create_buffer({kOddSize, "second"}, MemoryUsage::Upload);
    EXPECT_EQ(second.mapped(), first_memory);
    EXPECT_GE(kept - ctx().memory_stats().kept_bytes, kOddSize);
    EXPECT_EQ(ctx().memory_stats().allocations, before.allocations + 2);
}

TEST_F(MemoryReuse, ReleasedOnRequestAndNoneKeptWithAZeroBudget) {
    { Buffer b = ctx().create_buffer({kOddSize, "to keep"}, MemoryUsage::Upload); }
    EXPECT_GE(ctx().memory_stats().kept_bytes, kOddSize);
    ctx().release_kept_memory();
    EXPECT_EQ(ctx().memory_stats().kept_bytes, 0u);

    ContextOptions options = ContextOptions::from_environment();
    options.keep_freed_memory = 0;
    auto none = Context::create(options);
    { Buffer b = none->create_buffer({kOddSize, "freed"}, MemoryUsage::Upload); }
    EXPECT_EQ(none->memory_stats().kept_bytes, 0u);
    EXPECT_EQ(none->memory_stats().allocations, 0u);
}

// An image filled by the host holds exactly what was written, whether written in place or
// through staging; on a CPU device (lavapipe) a texel array's rows (4,096 texels, packed) are
// written in place: no staging buffer exists beside the image while the fill runs.
TEST_F(MemoryReuse, ImagesFilledInPlaceOnACpuDeviceNeedNoStaging) {
    for (const std::uint32_t width : {4096u, 300u}) {  // 300 x 16 bytes: rows the driver may pad
        const std::uint32_t before = ctx().memory_stats().allocations;
        std::uint32_t during = 0;
        Image image = ctx().create_image({width, 7, Format::RGBA32U, "filled"}, [&](std::span<std::byte> bytes) {
            during = ctx().memory_stats().allocations;
            for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = std::byte((i * 7 + 3) & 0xff);
        });
        const std::vector<std::byte> back = ctx().download(image);
        ASSERT_EQ(back.size(), std::size_t(width) * 7 * 16);
        for (std::size_t i = 0; i < back.size(); ++i)
            ASSERT_EQ(back[i], std::byte((i * 7 + 3) & 0xff)) << "byte " << i << " of width " << width;
        const VkPhysicalDeviceType type = ctx().device_info().type;
        if (width == 4096 && type == VK_PHYSICAL_DEVICE_TYPE_CPU) {
            EXPECT_EQ(during, before + 1) << "only the image's own memory";
        }
        if (type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU) {
            EXPECT_EQ(during, before + 2) << "the image and its staging";
        }
    }
}

// Failures become gimg::Error naming the pass, the call and the result; the validation harness
// itself is checked by provoking a hazard it must see.
#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"
#include "gimg/engine/texel_array.h"
#include "gimg/engine/upload.h"

#include "gpu_test.h"

#include "engine/scale_add_comp.h"

#include <glm/vec4.hpp>

#include <cstring>
#include <string>
#include <vector>

using namespace gimg;

namespace {
class EngineErrors : public gimg::test::GpuTest {};
const Spirv kScaleAdd = GIMG_SPIRV(gimg_spv_engine_scale_add_comp);
struct ScaleAdd {
    std::uint32_t count;
    float scale, offset;
};

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
}  // namespace

TEST_F(EngineErrors, WrongBindingsNameThePassAndTheProgram) {
    Buffer a = ctx().create_buffer({256, "a"});
    Graph g(ctx());
    auto h = g.import_buffer(a);
    g.add_compute_pass(
        "one binding short", [&](PassBuilder& b) { h = b.write(h, Access::ComputeReadWrite); },
        [=](Cmd& c) {
            c.dispatch(kScaleAdd, {1}, {h}, ScaleAdd{64, 1.0f, 0.0f});
        });
    Plan plan = g.compile();
    try {
        plan.execute();
        FAIL() << "a missing binding must fail";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidGraph);
        EXPECT_TRUE(contains(e.what(), "one binding short")) << e.what();
        EXPECT_TRUE(contains(e.what(), "scale_add")) << e.what();
    }
}

TEST_F(EngineErrors, UndeclaredResourcesAndWrongPushConstantsAreRejected) {
    Buffer a = ctx().create_buffer({256, "a"});
    Buffer b = ctx().create_buffer({256, "b"});
    {
        Graph g(ctx());
        auto ha = g.import_buffer(a);
        auto hb = g.import_buffer(b);
        g.add_compute_pass(
            "reads b without saying", [&](PassBuilder& p) { ha = p.write(ha, Access::ComputeWrite); },
            [=](Cmd& c) {
                c.dispatch(kScaleAdd, {1}, {hb, ha}, ScaleAdd{64, 1.0f, 0.0f});
            });
        Plan plan = g.compile();
        try {
            plan.execute();
            FAIL() << "an undeclared resource must fail";
        } catch (const Error& e) {
            EXPECT_TRUE(contains(e.what(), "did not declare")) << e.what();
            EXPECT_TRUE(contains(e.what(), "'b'")) << e.what();
        }
    }
    {
        Graph g(ctx());
        auto ha = g.import_buffer(a);
        auto hb = g.import_buffer(b);
        g.add_compute_pass(
            "short push",
            [&](PassBuilder& p) {
                p.read(ha, Access::ComputeRead);
                hb = p.write(hb, Access::ComputeWrite);
            },
            [=](Cmd& c) {
                c.dispatch(kScaleAdd, {1}, {ha, hb}, std::uint32_t(64));
            });
        Plan plan = g.compile();
        try {
            plan.execute();
            FAIL() << "too few push-constant bytes must fail";
        } catch (const Error& e) {
            EXPECT_TRUE(contains(e.what(), "12 bytes of push constants")) << e.what();
        }
    }
}

TEST_F(EngineErrors, ImpossibleAllocationsAreReportedNotCrashedOn) {
    try {
        Buffer huge = ctx().create_buffer({VkDeviceSize(1) << 45, "huge"});
        FAIL() << "a 32 TiB buffer cannot exist";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory) << e.what();
        EXPECT_TRUE(contains(e.what(), "'huge'")) << e.what();
    }
    // Bigger than the memory heap or one allocation may be: refused before Vulkan is asked.
    const VkDeviceSize too_big = VkDeviceSize(1) << 40;
    try {
        Buffer big = ctx().create_buffer({too_big / 1024 * 1023, "bigger than the heap"});
        FAIL() << "a 1023 GiB allocation cannot succeed";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory) << e.what();
        EXPECT_TRUE(contains(e.what(), "bigger than the heap")) << e.what();
    }
    // The context stays usable.
    Buffer fine = ctx().create_buffer({64, "fine"});
    std::uint32_t v = 7;
    ctx().upload(fine, &v, 4);
    std::uint32_t back = 0;
    ctx().download(fine, &back, 4);
    EXPECT_EQ(back, 7u);
}

TEST_F(EngineErrors, SynchronizationValidationSeesAMissingBarrier) {
    if (!ctx().validation_enabled()) GTEST_SKIP() << "validation is off";
    // A raw copy the pass does not declare: the graph cannot order it, and syncval must notice.
    Buffer a = ctx().create_buffer({256, "a"});
    Buffer b = ctx().create_buffer({256, "b"});
    Graph g(ctx());
    auto ha = g.import_buffer(a);
    auto hb = g.import_buffer(b);
    g.add_compute_pass(
        "write b",
        [&](PassBuilder& p) {
            p.read(ha, Access::ComputeRead);
            hb = p.write(hb, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch(kScaleAdd, {1}, {ha, hb}, ScaleAdd{64, 1.0f, 0.0f});
        });
    g.add_compute_pass(
        "undeclared copy",
        [&](PassBuilder& p) {
            p.read(ha, Access::TransferSrc);
            p.keep();
        },
        [=, vb = b.vk(), va = a.vk()](Cmd& c) {
            VkBufferCopy region{0, 0, 256};
            vkCmdCopyBuffer(c.vk(), va, vb, 1, &region);  // writes b: write-after-write hazard
        });
    const std::uint64_t before = ctx().validation_message_count();
    testing::internal::CaptureStderr();
    g.compile().execute();
    const std::string log = testing::internal::GetCapturedStderr();
    EXPECT_GT(ctx().validation_message_count(), before);
    EXPECT_TRUE(contains(log, "SYNC-HAZARD")) << log;
    accept_validation_messages();
}

TEST_F(EngineErrors, TexelArraysArePaddedWithZerosAndPartialUploadsAreRefusedUnlessAsked) {
    // A full image of 0xff bytes first, so a reused staging allocation would show through the padding.
    const std::vector<glm::uvec4> full(kTexelArrayRowWidth * 2, glm::uvec4(0xffffffffu));
    Image first = upload_texel_array(ctx(), full, Format::RGBA32U, "full");
    const std::vector<glm::uvec4> some{{1, 2, 3, 4}, {5, 6, 7, 8}, {9, 10, 11, 12}};
    Image padded = upload_texel_array(ctx(), some, Format::RGBA32U, "padded");
    const std::vector<std::byte> bytes = ctx().download(padded);
    ASSERT_EQ(bytes.size(), std::size_t(kTexelArrayRowWidth) * sizeof(glm::uvec4));
    std::vector<glm::uvec4> back(kTexelArrayRowWidth);
    std::memcpy(back.data(), bytes.data(), bytes.size());
    for (std::size_t i = 0; i < back.size(); ++i)
        ASSERT_EQ(back[i], i < some.size() ? some[i] : glm::uvec4(0u)) << "texel " << i;
    // Without zero_rest an upload must fill the image; with it, it must still fit.
    EXPECT_THROW(ctx().upload(padded, some.data(), sizeof(glm::uvec4) * some.size()), Error);
    const std::vector<glm::uvec4> too_many(kTexelArrayRowWidth + 1);
    EXPECT_THROW(ctx().upload(padded, too_many.data(), sizeof(glm::uvec4) * too_many.size(), true), Error);
}

TEST_F(EngineErrors, TexelCopiesMoveOnlyTheFirstTexelsAndRefuseMoreThanTheImageHolds) {
    const std::uint32_t n = kTexelArrayRowWidth + 5;  // a whole row and five texels of the next
    std::vector<std::uint32_t> words(n);
    for (std::uint32_t i = 0; i < n; ++i) words[i] = i * 7u + 1u;
    Buffer source = upload_buffer(ctx(), words, "words");
    Buffer back = ctx().create_buffer({n * 4ull, "back"});
    const std::vector<std::uint32_t> filled(2 * kTexelArrayRowWidth, 0xffffffffu);
    Image image = upload_texel_array(ctx(), filled, Format::R32U, "texels");
    Graph g(ctx());
    BufferHandle s = g.import_buffer(source), d = g.import_buffer(back);
    ImageHandle t = g.import_image(image);
    g.add_compute_pass(
        "in",
        [&](PassBuilder& b) {
            b.read(s, Access::TransferSrc);
            t = b.write(t, Access::TransferDst);
        },
        [=](Cmd& c) { c.copy_texels(s, t, n); });
    g.add_compute_pass(
        "out",
        [&](PassBuilder& b) {
            b.read(t, Access::TransferSrc);
            d = b.write(d, Access::TransferDst);
        },
        [=](Cmd& c) { c.copy_texels(t, d, n); });
    g.export_image(t, Access::TransferSrc);
    g.export_buffer(d, Access::TransferSrc);
    g.compile().execute();
    EXPECT_EQ(ctx().download<std::uint32_t>(back), words);
    const std::vector<std::byte> bytes = ctx().download(image);
    std::vector<std::uint32_t> texels(2 * kTexelArrayRowWidth);
    ASSERT_EQ(bytes.size(), texels.size() * 4);
    std::memcpy(texels.data(), bytes.data(), bytes.size());
    for (std::uint32_t i = 0; i < texels.size(); ++i)
        ASSERT_EQ(texels[i], i < n ? words[i] : 0xffffffffu) << "texel " << i;  // the rest untouched

    Buffer big = ctx().create_buffer({(2ull * kTexelArrayRowWidth + 1) * 4, "big"});
    Graph h(ctx());
    BufferHandle bh = h.import_buffer(big);
    ImageHandle th = h.import_image(image);
    h.add_compute_pass(
        "too many",
        [&](PassBuilder& b) {
            b.read(bh, Access::TransferSrc);
            th = b.write(th, Access::TransferDst);
        },
        [=](Cmd& c) { c.copy_texels(bh, th, 2 * kTexelArrayRowWidth + 1); });
    EXPECT_THROW(h.compile().execute(), Error);
}

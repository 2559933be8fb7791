// Uploads batched into one submission (Context::batch_uploads): what they upload is there when the
// batch returns and for any plan submitted inside it, and the staged ones cost one submission.
#include "gimg/engine/context.h"
#include "gimg/engine/graph.h"

#include "gpu_test.h"

#include <cstring>
#include <stdexcept>
#include <vector>

using namespace gimg;

class UploadBatch : public gimg::test::GpuTest {};

namespace {
constexpr std::uint32_t kWidth = 64, kHeight = 3;

std::vector<std::uint32_t> pattern(std::uint32_t seed) {
    std::vector<std::uint32_t> v(kWidth * kHeight);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::uint32_t(i * 2654435761u + seed);
    return v;
}

std::vector<std::uint32_t> words_of(const std::vector<std::byte>& bytes) {
    std::vector<std::uint32_t> v(bytes.size() / 4);
    std::memcpy(v.data(), bytes.data(), bytes.size());
    return v;
}
}  // namespace

// Image uploads always go through staging: three of them, a buffer upload and an image created
// with a fill make one submission in a batch and three or more without.
TEST_F(UploadBatch, StagedUploadsTakeOneSubmission) {
    std::vector<Image> images;
    for (int i = 0; i < 3; ++i) images.push_back(ctx().create_image({kWidth, kHeight, Format::R32U, "batched"}));
    Buffer buffer = ctx().create_buffer({kWidth * 4, "batched buffer"});
    const std::vector<std::uint32_t> words = pattern(99);
    Image filled;
    const std::uint64_t before = ctx().submission_count();
    ctx().batch_uploads([&] {
        for (int i = 0; i < 3; ++i) {
            const std::vector<std::uint32_t> p = pattern(std::uint32_t(i));
            ctx().upload(images[std::size_t(i)], p.data(), p.size() * 4);
        }
        ctx().upload(buffer, words.data(), kWidth * 4);
        filled = ctx().create_image({kWidth, kHeight, Format::R32U, "filled"}, [&](std::span<std::byte> bytes) {
            std::memcpy(bytes.data(), words.data(), bytes.size());
        });
        EXPECT_EQ(ctx().submission_count(), before) << "nothing is submitted inside the batch";
    });
    EXPECT_EQ(ctx().submission_count(), before + 1);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(words_of(ctx().download(images[std::size_t(i)])), pattern(std::uint32_t(i)));
    EXPECT_EQ(words_of(ctx().download(filled)), words);
    std::vector<std::uint32_t> back(kWidth);
    ctx().download(buffer, back.data(), kWidth * 4);
    EXPECT_EQ(back, std::vector<std::uint32_t>(words.begin(), words.begin() + kWidth));

    // The same uploads one by one: a submission each for the three images at least.
    const std::uint64_t unbatched = ctx().submission_count();
    for (int i = 0; i < 3; ++i) {
        const std::vector<std::uint32_t> p = pattern(std::uint32_t(i + 10));
        ctx().upload(images[std::size_t(i)], p.data(), p.size() * 4);
    }
    EXPECT_EQ(ctx().submission_count(), unbatched + 3);
}

// A plan submitted inside the batch reads what the batch uploaded before it, and a download inside
// it sees the upload: both submit the pending copies first. Nested batches submit once, at the end
// of the outermost.
TEST_F(UploadBatch, WorkSubmittedInsideSeesThePendingUploads) {
    Image image = ctx().create_image({kWidth, kHeight, Format::R32U, "source"});
    Buffer out = ctx().create_buffer({kWidth * kHeight * 4, "copied"}, MemoryUsage::Readback);
    const std::vector<std::uint32_t> p = pattern(7), q = pattern(8);
    std::vector<std::uint32_t> copied(kWidth * kHeight), seen;
    ctx().batch_uploads([&] {
        ctx().upload(image, p.data(), p.size() * 4);
        Graph g(ctx());
        auto src = g.import_image(image);
        auto dst = g.import_buffer(out);
        g.add_compute_pass(
            "copy",
            [&](PassBuilder& b) {
                b.read(src, Access::TransferSrc);
                dst = b.write(dst, Access::TransferDst);
            },
            [=](Cmd& c) { c.copy(src, dst); });
        g.export_buffer(dst, Access::HostRead);
        g.compile().execute();
        ctx().download(out, copied.data(), copied.size() * 4);
        ctx().batch_uploads([&] { ctx().upload(image, q.data(), q.size() * 4); });
        seen = words_of(ctx().download(image));
    });
    EXPECT_EQ(copied, p);
    EXPECT_EQ(seen, q);
}

// An exception inside the batch still submits what was recorded, so the image holds its upload.
TEST_F(UploadBatch, AnExceptionInsideStillSubmitsTheRecordedCopies) {
    Image image = ctx().create_image({kWidth, kHeight, Format::R32U, "before the throw"});
    const std::vector<std::uint32_t> p = pattern(3);
    EXPECT_THROW(ctx().batch_uploads([&] {
        ctx().upload(image, p.data(), p.size() * 4);
        throw std::runtime_error("inside the batch");
    }),
                 std::runtime_error);
    EXPECT_EQ(words_of(ctx().download(image)), p);
    // And the context is out of batch mode: the next upload submits at once.
    const std::uint64_t before = ctx().submission_count();
    ctx().upload(image, p.data(), p.size() * 4);
    EXPECT_EQ(ctx().submission_count(), before + 1);
}

#include "gpu_test.h"

#include "test_data.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

namespace gimg::test {

namespace {

std::unique_ptr<Context>& context_slot() {
    static std::unique_ptr<Context> ctx;
    return ctx;
}

std::uint64_t& accepted_messages() {
    static std::uint64_t n = 0;
    return n;
}
std::uint64_t unexpected_messages() { return context_slot()->validation_message_count() - accepted_messages(); }

bool validation_wanted() {
    const char* v = std::getenv("GIMG_VALIDATION");
    return !(v && std::string(v) == "0");
}

class GpuEnvironment : public ::testing::Environment {
public:
    void TearDown() override {
        auto& ctx = context_slot();
        if (!ctx) return;
        const std::string line = ctx->device_info().summary() + " | validation " +
                                 (ctx->validation_enabled() ? "on (core + synchronization)" : "OFF") +
                                 " | unexpected validation messages: " + std::to_string(unexpected_messages());
        std::printf("GPU tests ran on: %s\n", line.c_str());
        std::ofstream(output_dir("") / "gpu-report.txt", std::ios::app) << line << "\n";
        ctx.reset();
    }
};

[[maybe_unused]] ::testing::Environment* const environment = ::testing::AddGlobalTestEnvironment(new GpuEnvironment);

}  // namespace

Context& gpu() {
    auto& ctx = context_slot();
    if (!ctx) {
        ContextOptions options = ContextOptions::from_environment();
        options.validation = validation_wanted();
        options.require_validation = options.validation;
        ctx = Context::create(options);
    }
    return *ctx;
}

void GpuTest::SetUp() {
    ctx_ = &gpu();
    messages_at_start_ = ctx_->validation_message_count();
    RecordProperty("device", ctx_->device_info().name);
}

void GpuTest::accept_validation_messages() {
    accepted_messages() += ctx_->validation_message_count() - messages_at_start_;
    messages_at_start_ = ctx_->validation_message_count();
}

void GpuTest::TearDown() {
    if (!ctx_) return;  // SetUp failed (no device, or validation asked for and missing): already reported
    EXPECT_EQ(ctx_->validation_message_count(), messages_at_start_)
        << "the validation layer reported problems during this test (see stderr)";
}

}  // namespace gimg::test

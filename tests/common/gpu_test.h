#pragma once
// GPU tests: one Context per test process, with the Khronos validation layer and synchronization
// validation required (GIMG_VALIDATION=0 alone turns it off, for timing runs). Every test fails if
// validation reported anything while it ran. At exit the process appends one line (device,
// validation, messages) to test-output/gpu-report.txt, which ./run test prints.

#include "gimg/engine/context.h"

#include <gtest/gtest.h>

namespace gimg::test {

Context& gpu();

class GpuTest : public ::testing::Test {
protected:
    void SetUp() override;
    void TearDown() override;
    Context& ctx() { return *ctx_; }
    // For tests that provoke validation messages on purpose, after checking them.
    void accept_validation_messages();

private:
    Context* ctx_ = nullptr;
    std::uint64_t messages_at_start_ = 0;
};

}  // namespace gimg::test

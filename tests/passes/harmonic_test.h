#pragma once
// The fixture of the harmonic spherical method's GPU tests: it needs shaderFloat64 and the
// multigrid's two-channel storage images, and skips with the reason where the device lacks them.
#include "gpu_test.h"

namespace gimg::test {

class HarmonicGpuTest : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        if (!ctx().device_info().shader_float64) GTEST_SKIP() << "device has no shaderFloat64";
        if (!ctx().device_info().storage_image_extended_formats)
            GTEST_SKIP() << "device has no shaderStorageImageExtendedFormats (the multigrid's RG32F vectors)";
    }
};

}  // namespace gimg::test

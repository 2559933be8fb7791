// SPIR-V reflection builds the pipeline layouts, so it is checked against shaders whose layout
// is known: bindings and their types, push-constant size, local size.
#include "spirv_reflect.h"

#include "gimg/engine/error.h"

#include "engine/jacobi1d_comp.h"
#include "engine/pixel_triangle_vert.h"
#include "engine/sampled_and_storage_comp.h"

#include <gtest/gtest.h>

using namespace gimg;

TEST(SpirvReflect, StorageBuffersPushConstantsAndLocalSize) {
    auto r = detail::reflect_spirv(GIMG_SPIRV(gimg_spv_engine_jacobi1d_comp));
    EXPECT_EQ(r.stage, VK_SHADER_STAGE_COMPUTE_BIT);
    ASSERT_EQ(r.bindings.size(), 2u);
    EXPECT_EQ(r.bindings[0].binding, 0u);
    EXPECT_EQ(r.bindings[0].type, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    EXPECT_EQ(r.bindings[1].binding, 1u);
    EXPECT_EQ(r.push_constant_bytes, 8u);  // uint count; float alpha
    EXPECT_EQ(r.local_size[0], 64u);
    EXPECT_EQ(r.local_size[1], 1u);
}

TEST(SpirvReflect, ImagesUniformsAndAVertexStage) {
    auto r = detail::reflect_spirv(GIMG_SPIRV(gimg_spv_engine_sampled_and_storage_comp));
    ASSERT_EQ(r.bindings.size(), 3u);
    EXPECT_EQ(r.bindings[0].type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
    EXPECT_EQ(r.bindings[1].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
    EXPECT_EQ(r.bindings[2].type, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
    EXPECT_EQ(r.push_constant_bytes, 80u);  // mat4 (64) + vec3 at 64 + float at 76
    EXPECT_EQ(r.local_size[0], 8u);
    EXPECT_EQ(r.local_size[1], 8u);

    auto v = detail::reflect_spirv(GIMG_SPIRV(gimg_spv_engine_pixel_triangle_vert));
    EXPECT_EQ(v.stage, VK_SHADER_STAGE_VERTEX_BIT);
    EXPECT_EQ(v.push_constant_bytes, 8u);
}

TEST(SpirvReflect, GarbageIsRejectedWithTheShadersName) {
    const std::uint32_t garbage[] = {0x12345678u, 1, 2, 3, 4, 5};
    try {
        detail::reflect_spirv(Spirv{garbage, 6, "garbage.comp"});
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("garbage.comp"), std::string::npos);
    }
}

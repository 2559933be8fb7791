#pragma once
// Where tests find real meshes and put their outputs.

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

namespace gimg::test {

// ../shared/meshes beside the checkout, or $GIMG_MESH_DIR. Empty when neither exists.
inline std::optional<std::filesystem::path> mesh_dir() {
    if (const char* env = std::getenv("GIMG_MESH_DIR"); env && *env) {
        if (std::filesystem::is_directory(env)) return std::filesystem::path(env);
        return std::nullopt;
    }
    std::filesystem::path p = GIMG_DEFAULT_MESH_DIR;
    if (std::filesystem::is_directory(p)) return std::filesystem::canonical(p);
    return std::nullopt;
}

// Path of a shared mesh, or nullopt when the folder or the file is missing.
inline std::optional<std::filesystem::path> shared_mesh(const std::string& name) {
    auto dir = mesh_dir();
    if (!dir) return std::nullopt;
    auto p = *dir / name;
    if (!std::filesystem::exists(p)) return std::nullopt;
    return p;
}

// A folder for this test's output files (kept after the run for inspection).
inline std::filesystem::path output_dir(const std::string& sub) {
    auto p = std::filesystem::path(GIMG_TEST_OUTPUT_DIR) / sub;
    std::filesystem::create_directories(p);
    return p;
}

}  // namespace gimg::test

// Skips the current test with a clear message when a shared mesh is absent.
#define GIMG_REQUIRE_SHARED_MESH(var, name)                                                       \
    auto var##_opt = ::gimg::test::shared_mesh(name);                                             \
    if (!var##_opt) GTEST_SKIP() << "shared mesh " << (name) << " not found (set GIMG_MESH_DIR)"; \
    const std::filesystem::path var = *var##_opt

#pragma once
// Test mesh files: the tiny seed meshes in tests/data/meshes, and files written on the fly.

#include "test_data.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

namespace gimg::test {

// tests/data/meshes/<name>: always present (part of the source tree).
inline std::filesystem::path seed_mesh(const std::string& name) {
    return std::filesystem::path(GIMG_TEST_DATA_DIR) / "meshes" / name;
}

// Writes `bytes` to test-output/<sub>/<name> (replacing it) and returns its path.
inline std::filesystem::path write_file(const std::string& sub, const std::string& name, std::string_view bytes) {
    const std::filesystem::path p = output_dir(sub) / name;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return p;
}

inline std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream contents;
    contents << in.rdbuf();
    return contents.str();
}

}  // namespace gimg::test

#pragma once
// Where the benchmarks find meshes: ../shared/meshes (GIMG_MESH_DIR) and the large ones that
// ../shared/meshes/fetch_large.sh fetches (GIMG_LARGE_MESH_DIR, default ~/.cache/gimg-large-meshes).
#include <cstdlib>
#include <filesystem>

namespace gimg::cli {

inline std::filesystem::path env_or(const char* name, const std::filesystem::path& fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::filesystem::path(v) : fallback;
}

inline std::filesystem::path shared_mesh_dir() { return env_or("GIMG_MESH_DIR", "../shared/meshes"); }

inline std::filesystem::path large_mesh_dir() {
    const char* home = std::getenv("HOME");
    return env_or("GIMG_LARGE_MESH_DIR", std::filesystem::path(home ? home : ".") / ".cache/gimg-large-meshes");
}

}  // namespace gimg::cli

#pragma once
// --json FILE output shared by every command: pretty-printed, snake_case keys, written atomically,
// plus the figures every solver or projection reports (DESIGN.md): device, gpu_memory_mb,
// peak_rss_mb; and submissions and device_wait_seconds.

#include "gimg/engine/context.h"
#include "gimg/geometry/atomic_file.h"

#include <nlohmann/json.hpp>

#include <sys/resource.h>

#include <cstdio>
#include <string>

namespace gimg::cli {

// "-" writes to standard output.
inline void write_json(const std::string& path, const nlohmann::json& j) {
    if (path.empty()) return;
    const std::string text = j.dump(2) + "\n";
    if (path == "-") {
        std::fwrite(text.data(), 1, text.size(), stdout);
        return;
    }
    gimg::geo::write_file_atomically(path, text);
}

inline double peak_rss_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // Linux reports kilobytes
}

// device, gpu_memory_mb (the engine's peak device allocation), submissions and device_wait_seconds
// (the queue submissions so far and the host's time waiting for them), and peak_rss_mb.
inline void add_machine_figures(nlohmann::json& j, const Context* ctx) {
    if (ctx) {
        j["device"] = ctx->device_info().name;
        j["gpu_memory_mb"] = double(ctx->memory_stats().peak_allocated_bytes) / (1024.0 * 1024.0);
        j["submissions"] = ctx->submission_count();
        j["device_wait_seconds"] = ctx->device_wait_seconds();
    }
    j["peak_rss_mb"] = peak_rss_mb();
}

}  // namespace gimg::cli

#pragma once
// --json FILE output shared by every command: pretty-printed, snake_case keys, written atomically.

#include "gimg/geometry/atomic_file.h"

#include <nlohmann/json.hpp>

#include <string>

namespace gimg::cli {

inline void write_json(const std::string& path, const nlohmann::json& j) {
    if (path.empty()) return;
    gimg::geo::write_file_atomically(path, j.dump(2) + "\n");
}

}  // namespace gimg::cli

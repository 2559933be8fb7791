#pragma once
// Whole-file writes that never leave a half-written file: write to a temporary name in the same
// folder, then rename over the target.

#include <filesystem>
#include <string_view>

namespace gimg::geo {

// Throws InputError (naming the path) when the folder is missing or not writable.
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace gimg::geo

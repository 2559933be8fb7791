#pragma once
// frame.json, shared by the ordinary and the hierarchical cylindrical images: the frame as JSON,
// read back with every check, and the stamp that ties an image to the frame.json written with it.
#include "gimg/passes/cylinder.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gimg::passes::detail {

// rotation (rows), translation, scale and the formula that joins them.
nlohmann::json frame_json(const CylinderFrame& frame);
// Throws geo::InputError for a missing file, a folder or malformed JSON.
nlohmann::json read_frame_json(const std::filesystem::path& path);
// Throws geo::InputError unless the rotation is a rotation and scale and translation are finite.
CylinderFrame frame_of(const nlohmann::json& j, const std::filesystem::path& path);
// FNV-1a over the size, mask and the values of valid pixels, as 16 hex digits.
std::string stamp_of(std::uint32_t width, std::uint32_t height, const std::vector<std::uint8_t>& valid,
                     const std::vector<float>& values);

}  // namespace gimg::passes::detail

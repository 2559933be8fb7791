// frame.json, shared by the ordinary and the hierarchical cylindrical images.
#include "frame_json.h"

#include "gimg/geometry/error.h"
#include "json_problem.h"

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>

namespace gimg::passes::detail {

nlohmann::json frame_json(const CylinderFrame& frame) {
    nlohmann::json j;
    j["rotation"] = nlohmann::json::array();
    for (int r = 0; r < 3; ++r)
        j["rotation"].push_back({frame.rotation[0][r], frame.rotation[1][r], frame.rotation[2][r]});
    j["translation"] = {frame.translation.x, frame.translation.y, frame.translation.z};
    j["scale"] = frame.scale;
    j["to_cylinder"] = "p_cylinder = scale * rotation * p + translation (rotation as rows)";
    return j;
}

nlohmann::json read_frame_json(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw geo::InputError(path.string() + " is a folder, not a frame.json");
    std::ifstream in(path);
    if (!in)
        throw geo::InputError("cannot read " + path.string() + ": no such file (it is written beside distance.exr)");
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw geo::InputError(path.string() + " is not a gimg frame.json: " + detail::json_problem(e));
    }
}

CylinderFrame frame_of(const nlohmann::json& j, const std::filesystem::path& path) {
    CylinderFrame f;
    try {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) f.rotation[c][r] = j.at("rotation").at(r).at(c).get<double>();
        for (int k = 0; k < 3; ++k) f.translation[k] = j.at("translation").at(k).get<double>();
        f.scale = j.at("scale").get<double>();
    } catch (const nlohmann::json::exception& e) {
        throw geo::InputError(path.string() + " is not a gimg frame.json: " + detail::json_problem(e));
    }
    if (!(f.scale > 0.0) || !std::isfinite(f.scale)) throw geo::InputError(path.string() + ": scale must be positive");
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(f.translation[k])) throw geo::InputError(path.string() + ": translation is not finite");
    // A rotation: orthonormal rows (to the precision a dump of doubles keeps) and no mirror.
    const glm::dmat3 should_be_identity = glm::transpose(f.rotation) * f.rotation;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            if (!(std::abs(should_be_identity[c][r] - (r == c ? 1.0 : 0.0)) <= 1e-9))
                throw geo::InputError(path.string() + ": rotation is not a rotation (its rows are not orthonormal)");
    if (!(glm::determinant(f.rotation) > 0.0)) throw geo::InputError(path.string() + ": rotation is a mirror");
    return f;
}

std::string stamp_of(std::uint32_t width, std::uint32_t height, const std::vector<std::uint8_t>& valid,
                     const std::vector<float>& values) {
    std::uint64_t h = 14695981039346656037ull;
    auto mix = [&](const void* data, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
    };
    mix(&width, 4);
    mix(&height, 4);
    for (std::size_t i = 0; i < valid.size(); ++i) {
        mix(&valid[i], 1);
        if (valid[i]) mix(&values[i], 4);
    }
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
    return text;
}

}  // namespace gimg::passes::detail

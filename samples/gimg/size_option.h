#pragma once
// "WxH" command-line sizes.

#include "gimg/geometry/error.h"

#include <array>
#include <cstdint>
#include <string>

namespace gimg::cli {

// Parses "540x270"; throws InputError (exit 2) for anything else or a side outside [1, max_side].
inline std::array<std::uint32_t, 2> parse_size(const std::string& text, std::uint32_t max_side = 16384) {
    const auto x = text.find('x');
    auto side = [&](const std::string& s) -> std::uint32_t {
        if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos) return 0;
        return std::uint32_t(std::stoul(s));
    };
    const std::uint32_t w = x == std::string::npos ? 0 : side(text.substr(0, x));
    const std::uint32_t h = x == std::string::npos ? 0 : side(text.substr(x + 1));
    if (w == 0 || h == 0 || w > max_side || h > max_side)
        throw geo::InputError("--size takes WxH with sides from 1 to " + std::to_string(max_side) + ", got '" + text +
                              "'");
    return {w, h};
}

}  // namespace gimg::cli

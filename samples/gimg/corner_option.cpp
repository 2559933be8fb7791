#include "corner_option.h"

#include "gimg/geometry/error.h"

#include <cstdlib>
#include <sstream>

namespace gimg::cli {

std::vector<std::uint32_t> parse_corners(const std::string& text, const passes::QuadRegionCutter& cutter) {
    if (text == "auto") {
        const auto c = passes::flattest_square_corners(cutter);
        return {c.begin(), c.end()};
    }
    if (text.rfind("auto:", 0) == 0) {
        char* end = nullptr;
        const double side = std::strtod(text.c_str() + 5, &end);
        if (*end || !(side > 0.0 && side <= 2.0))
            throw geo::InputError(
                "--corners auto:F takes the square's side F in bounding-box diagonals (0 to 2), got '" + text + "'");
        const auto c = passes::flattest_square_corners(cutter, side);
        return {c.begin(), c.end()};
    }
    std::vector<std::uint32_t> c;
    std::istringstream in(text);
    for (;;) {
        long long v = -1;
        if (!(in >> v) || v < 0 || v > 0xfffffffe) break;
        c.push_back(std::uint32_t(v));
        char comma = 0;
        if (!(in >> comma)) {
            if (c.size() == 3 || c.size() == 4) return c;
            break;
        }
        if (comma != ',') break;
    }
    throw geo::InputError(
        "--corners takes four vertex indices A,B,C,D (or three for a triangle), counter-clockwise, "
        "or auto, got '" +
        text + "'");
}

}  // namespace gimg::cli

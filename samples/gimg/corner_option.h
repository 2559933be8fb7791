#pragma once
// The --corners option of gimg quadmap and deform, and of gimg bench quadmap's regions.
#include "gimg/passes/quad_region.h"

#include <cstdint>
#include <string>
#include <vector>

namespace gimg::cli {

// Four vertex indices A,B,C,D (a quad region), three (a triangle region), auto (a square of 0.2
// diagonals around the flattest vertex) or auto:F (of F diagonals). Throws geo::InputError.
std::vector<std::uint32_t> parse_corners(const std::string& text, const passes::QuadRegionCutter& cutter);

}  // namespace gimg::cli

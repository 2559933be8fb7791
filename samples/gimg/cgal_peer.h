#pragma once
// CGAL 5.5's fixed-border parameterizations onto the unit square: the peers a user would reach
// for, timed beside gimg's parameterization geometry images by `gimg bench gim`. Built only when
// Debian's libcgal-dev is present (GIMG_HAS_CGAL).

#include "gimg/geometry/mesh.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

namespace gimg::cli {

enum class CgalSquareMap { MeanValue, DiscreteAuthalic, DiscreteConformal, IterativeAuthalic };

// "cgal-mean-value", "cgal-discrete-authalic", "cgal-discrete-conformal", "cgal-iterative-authalic"
const char* cgal_square_map_name(CgalSquareMap method);

bool cgal_available();  // false when built without CGAL

struct CgalSquareMapResult {
    std::vector<glm::dvec2> uv;  // one per mesh vertex (iterative authalic may leave the square); empty on failure
    double seconds = 0.0;        // wall time of CGAL's parameterize() call alone (building the Surface_mesh excluded)
    std::string error;           // empty on success; CGAL's error text otherwise
};

// `mesh`: one component, manifold, one boundary loop (the caller has checked). `corners`: four
// boundary vertex indices in boundary order, mapped to (0,0), (1,0), (1,1), (0,1) in that order.
// `iterations` is used only by IterativeAuthalic (CGAL's iteration count; CGAL keeps its best iterate).
CgalSquareMapResult cgal_square_map(const geo::Mesh& mesh, const std::array<std::uint32_t, 4>& corners,
                                    CgalSquareMap method, unsigned iterations = 15);

}  // namespace gimg::cli

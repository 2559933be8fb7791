#pragma once
// An offset lattice's weights at fixed parameter points: per point the 4 x 4 control points around
// it (the only ones whose basis values are not zero) and the products of their basis values. The
// interactive editor keeps them per map, so an offset edit costs 16 products a region vertex.
#include "gimg/passes/quad_region.h"

#include <array>
#include <cstdint>
#include <vector>

namespace gimg::passes {

class LatticeWeights {
public:
    LatticeWeights(const OffsetLattice& shape, const std::vector<glm::dvec2>& uv);
    // Whether these weights were made for the lattice's columns, rows and fixed layers.
    bool fits(const OffsetLattice& lattice) const;
    // lattice.evaluate(uv[i]) with the same terms in the same order (zero terms left out).
    glm::dvec3 offset(std::size_t i, const OffsetLattice& lattice) const;

private:
    std::uint32_t columns_ = 0, rows_ = 0;
    int fixed_layers_ = 0;
    std::vector<std::uint32_t> first_p_, first_q_;  // per point: the block's first column and row
    std::vector<std::array<double, 16>> weight_;    // per point: B_p(u) B_q(v), row q - first_q major
};

}  // namespace gimg::passes

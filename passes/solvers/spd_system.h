#pragma once
// The form in which the GPU conjugate gradients take a sparse symmetric positive definite system:
// what is left of A x = b once the Dirichlet rows are eliminated (gimg/passes/solvers.h builds it
// from a full matrix). Right-hand sides come in pairs, as the shaders' vectors are dvec2.
#include <glm/vec2.hpp>

#include <cstdint>
#include <vector>

namespace gimg::passes::detail {

struct SpdSystem {
    std::vector<std::uint32_t> row_offsets;  // rows + 1, into columns / values
    std::vector<std::uint32_t> columns;      // off-diagonal entries only
    std::vector<double> values;
    std::vector<double> diagonal;
    std::vector<glm::dvec2> rhs;
    std::vector<glm::dvec2> start;  // the first guess
    std::size_t rows() const { return diagonal.size(); }
};

}  // namespace gimg::passes::detail

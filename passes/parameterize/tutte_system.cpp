// The weighted Tutte system shared by the square maps and the quad-region maps.
#include "parameterize/tutte_system.h"

namespace gimg::passes::detail {

// Rows of interior vertices: u_i - sum_j w_ij u_j = 0 (weights normalised); boundary rows fixed.
LinearSystem tutte_system(const geo::MeshAdjacency& adj, const std::vector<double>& weights,
                          const std::vector<std::uint8_t>& interior, const std::vector<glm::dvec2>& fixed_uv,
                          const std::vector<glm::dvec2>& start) {
    LinearSystem s;
    const std::size_t n = adj.vertex_count();
    s.a.size = n;
    s.rhs_count = 2;
    s.a.offsets.reserve(n + 1);
    for (std::size_t i = 0; i < n; ++i) {
        s.a.columns.push_back(std::uint32_t(i));
        s.a.values.push_back(1.0);
        if (interior[i]) {
            const auto nb = adj.neighbors(i);
            for (std::size_t k = 0; k < nb.size(); ++k) {
                s.a.columns.push_back(nb[k]);
                s.a.values.push_back(-weights[adj.vertex_vertex_offsets[i] + k]);
            }
        }
        s.a.offsets.push_back(std::uint32_t(s.a.columns.size()));
    }
    s.b.assign(2 * n, 0.0);
    s.fixed.resize(n);
    s.fixed_values.assign(2 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        s.fixed[i] = interior[i] ? 0 : 1;
        s.fixed_values[2 * i] = fixed_uv[i].x, s.fixed_values[2 * i + 1] = fixed_uv[i].y;
    }
    if (!start.empty()) {
        s.start.resize(2 * n);
        for (std::size_t i = 0; i < n; ++i) s.start[2 * i] = start[i].x, s.start[2 * i + 1] = start[i].y;
    }
    return s;
}

}  // namespace gimg::passes::detail

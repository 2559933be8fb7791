// A first guess for the next system of a run from the solutions of the earlier ones.
#include "gimg/geometry/error.h"
#include "gimg/passes/solvers.h"

#include <Eigen/Dense>

#include <string>

namespace gimg::passes {

void project_start(LinearSystem& system, const std::vector<std::vector<double>>& past) {
    const std::size_t n = system.a.size, m = system.rhs_count, len = n * m;
    if (past.empty()) return;
    for (const auto& x : past)
        if (x.size() != len)
            throw geo::InputError("project_start: a past solution has " + std::to_string(x.size()) +
                                  " values, the system " + std::to_string(len));
    const std::vector<double>& last = past.back();
    auto free_row = [&](std::size_t i) { return system.fixed.empty() || !system.fixed[i]; };
    auto fixed_value = [&](std::size_t k) { return system.fixed_values.empty() ? 0.0 : system.fixed_values[k]; };
    // Fixed rows hold their values in every guess; the steps between solutions move free rows only.
    std::vector<double> start(len);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < m; ++c) start[i * m + c] = free_row(i) ? last[i * m + c] : fixed_value(i * m + c);
    const std::size_t steps = past.size() - 1;
    auto times = [&](const std::vector<double>& x, std::size_t i, std::size_t c) {
        double sum = 0.0;
        for (std::uint32_t k = system.a.offsets[i]; k < system.a.offsets[i + 1]; ++k)
            sum += system.a.values[k] * x[system.a.columns[k] * m + c];
        return sum;
    };
    std::vector<std::vector<double>> step(steps, std::vector<double>(len, 0.0));
    for (std::size_t s = 0; s < steps; ++s)
        for (std::size_t i = 0; i < n; ++i)
            if (free_row(i))
                for (std::size_t c = 0; c < m; ++c) step[s][i * m + c] = last[i * m + c] - past[s][i * m + c];

    std::vector<std::size_t> rows;
    for (std::size_t i = 0; i < n; ++i)
        if (free_row(i)) rows.push_back(i);
    // Per right-hand side: start + sum_s g_s step_s with the g that minimise |b - A x| on the free
    // rows, a least-squares problem of `steps` unknowns (rank-revealing, as steps are often nearly
    // parallel).
    for (std::size_t c = 0; c < m && steps > 0; ++c) {
        Eigen::MatrixXd w(Eigen::Index(rows.size()), Eigen::Index(steps));
        Eigen::VectorXd r(Eigen::Index(rows.size()));
        for (std::size_t k = 0; k < rows.size(); ++k) {
            const std::size_t i = rows[k];
            r[Eigen::Index(k)] = (system.b.empty() ? 0.0 : system.b[i * m + c]) - times(start, i, c);
            for (std::size_t s = 0; s < steps; ++s) w(Eigen::Index(k), Eigen::Index(s)) = times(step[s], i, c);
        }
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(w);
        qr.setThreshold(1e-10);
        const Eigen::VectorXd g = qr.solve(r);
        if (!g.allFinite()) continue;
        for (std::size_t i : rows)
            for (std::size_t s = 0; s < steps; ++s) start[i * m + c] += g[Eigen::Index(s)] * step[s][i * m + c];
    }
    system.start = std::move(start);
}

}  // namespace gimg::passes

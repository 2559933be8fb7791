#pragma once
// Medians of repeated timings, for the benchmarks (DESIGN.md: several runs, the median).

#include <algorithm>
#include <chrono>
#include <vector>

namespace gimg::cli {

inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Milliseconds `work` takes, once.
template <class Work>
double time_ms(Work&& work) {
    const auto start = std::chrono::steady_clock::now();
    work();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace gimg::cli

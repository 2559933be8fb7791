#pragma once
// Parallel primitives as render-graph passes: inclusive prefix sum and sum reduction of uint32
// arrays (exact, deterministic). Building blocks for compaction (reconstruction), counting and
// convergence tests of the solvers.

#include "gimg/engine/graph.h"

#include <cstdint>
#include <string>

namespace gimg::passes {

// out[i] = in[0] + ... + in[i] for i < count. Adds one or more passes named "<name> ..." (names
// must be unique in the graph). Returns the new version of `out`.
BufferHandle add_inclusive_scan(Graph& graph, BufferHandle in, BufferHandle out, std::uint32_t count,
                                const std::string& name = "scan");

// out[0] = in[0] + ... + in[count-1] (modulo 2^32), by a fixed tree. Returns the new version of
// `out` (at least 4 bytes).
BufferHandle add_reduce_sum(Graph& graph, BufferHandle in, BufferHandle out, std::uint32_t count,
                            const std::string& name = "sum");

// How add_reduce_sum_f64 sums a block: `automatic` takes subgroup arithmetic where the graph's
// device has it (4x faster on lavapipe), else the shared-memory tree.
enum class ReduceF64Method { automatic, tree, subgroup };

// out[c] = sum over i < count of in[i * width + c] for c < width, in double, in a fixed order (the
// same result on every run on one device, unlike float atomics). Needs shaderFloat64; `subgroup`
// needs DeviceInfo::subgroup_arithmetic (gimg::Error otherwise). Returns the new version of `out`
// (at least 8 * width bytes).
BufferHandle add_reduce_sum_f64(Graph& graph, BufferHandle in, BufferHandle out, std::uint32_t count,
                                std::uint32_t width, const std::string& name = "sum f64",
                                ReduceF64Method method = ReduceF64Method::automatic);

}  // namespace gimg::passes

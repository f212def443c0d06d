// Which of the engine's paths runs the trajectories of a V funnel: the scalar engine, one
// trajectory at a time, or a batched path with one trajectory per lane of a SIMD vector
// (docs/performance.md). Every path gives the same results, bit for bit.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace funnel {

/// The paths this CPU can run, narrowest first: "scalar", then those of "sse4" (2 lanes),
/// "avx2" (4 lanes) and "avx512" (8 lanes) that it supports.
std::vector<std::string> simd_paths();

/// The path in use: the widest one unless the environment variable FUNNEL_SIMD (read once, at
/// the first use) or set_simd_path chose another.
std::string simd_path();

/// Chooses the path for every later simulation; false (and nothing changes) if `name` is not
/// one of simd_paths(). Not to be called while simulations run.
bool set_simd_path(std::string_view name);

/// Lanes of the path in use (1 for "scalar").
int simd_lanes();

}  // namespace funnel

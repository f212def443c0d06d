// Counter-based random numbers: every value is a pure function of (seed, stream, index), so an
// ensemble's samples are the same whatever the thread count or the split of the work.
#pragma once

#include <cstdint>

namespace funnel {

/// Philox4x32-10 (Salmon et al., SC'11): 128-bit counter, 64-bit key; returns the first two
/// 32-bit words of the output block as one 64-bit integer.
std::uint64_t philox(std::uint64_t key, std::uint64_t counter_hi, std::uint64_t counter_lo);

/// A uniform double in (0, 1) (53 random bits, never 0 or 1) for (seed, stream, index).
double uniform01(std::uint64_t seed, std::uint64_t stream, std::uint64_t index);

/// A standard normal deviate for (seed, stream, index) (Box-Muller from two uniforms of the
/// sub-streams 2 stream and 2 stream + 1).
double standard_normal(std::uint64_t seed, std::uint64_t stream, std::uint64_t index);

}  // namespace funnel

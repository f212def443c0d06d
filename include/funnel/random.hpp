// Counter-based random numbers (Philox4x64-10): every draw is a pure function of
// (seed, stream, index), so results do not depend on the order or the thread that draws them.
#pragma once

#include <array>
#include <cstdint>

namespace funnel {

/// The Philox4x64-10 block cipher of Salmon et al. (SC'11): 4 x 64 random bits for a 256-bit
/// counter and a 128-bit key.
std::array<std::uint64_t, 4> philox4x64(std::array<std::uint64_t, 4> counter, std::array<std::uint64_t, 2> key);

/// A uniform double in the open interval (0, 1), 53 random bits: lane 0..3 of the block of
/// counter (index, stream, 0, 0) under key (seed, 0). Distinct (seed, stream, index, lane)
/// give independent draws.
double uniform(std::uint64_t seed, std::uint64_t stream, std::uint64_t index, int lane = 0);

/// A standard normal deviate (mean 0, variance 1) by the Box-Muller transform of the same block:
/// lanes 0 and 1 use the block's words 0 and 1 (cosine and sine), lanes 2 and 3 its words 2 and 3.
double normal(std::uint64_t seed, std::uint64_t stream, std::uint64_t index, int lane = 0);

}  // namespace funnel

// Philox4x64-10 and the uniform and normal draws built on it.
#include "funnel/random.hpp"

#include <cmath>
#include <numbers>

namespace funnel {

namespace {

/// High and low 64 bits of the 128-bit product a * b, from 32-bit halves (portable C++).
inline void mul_hi_lo(std::uint64_t a, std::uint64_t b, std::uint64_t& hi, std::uint64_t& lo) {
  const std::uint64_t a_lo = a & 0xFFFFFFFFu, a_hi = a >> 32, b_lo = b & 0xFFFFFFFFu, b_hi = b >> 32;
  const std::uint64_t ll = a_lo * b_lo, lh = a_lo * b_hi, hl = a_hi * b_lo, hh = a_hi * b_hi;
  const std::uint64_t mid = (ll >> 32) + (lh & 0xFFFFFFFFu) + (hl & 0xFFFFFFFFu);
  lo = (mid << 32) | (ll & 0xFFFFFFFFu);
  hi = hh + (lh >> 32) + (hl >> 32) + (mid >> 32);
}

/// The block's 64-bit word as a double in (0, 1): the top 53 bits, offset by half a step.
inline double to_unit(std::uint64_t bits) {
  return (static_cast<double>(bits >> 11) + 0.5) * 0x1.0p-53;
}

}  // namespace

std::array<std::uint64_t, 4> philox4x64(std::array<std::uint64_t, 4> c, std::array<std::uint64_t, 2> k) {
  // Multipliers and Weyl key increments of the reference implementation (Random123).
  constexpr std::uint64_t m0 = 0xD2E7470EE14C6C93ULL, m1 = 0xCA5A826395121157ULL;
  constexpr std::uint64_t w0 = 0x9E3779B97F4A7C15ULL, w1 = 0xBB67AE8584CAA73BULL;
  for (int round = 0; round < 10; ++round) {
    if (round > 0) {
      k[0] += w0;
      k[1] += w1;
    }
    std::uint64_t hi0, lo0, hi1, lo1;
    mul_hi_lo(m0, c[0], hi0, lo0);
    mul_hi_lo(m1, c[2], hi1, lo1);
    c = {hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0};
  }
  return c;
}

double uniform(std::uint64_t seed, std::uint64_t stream, std::uint64_t index, int lane) {
  const auto block = philox4x64({index, stream, 0, 0}, {seed, 0});
  return to_unit(block[static_cast<unsigned>(lane) & 3u]);
}

double normal(std::uint64_t seed, std::uint64_t stream, std::uint64_t index, int lane) {
  const auto block = philox4x64({index, stream, 0, 0}, {seed, 0});
  const unsigned pair = lane >= 2 ? 2u : 0u;
  const double radius = std::sqrt(-2.0 * std::log(to_unit(block[pair])));
  const double angle = 2.0 * std::numbers::pi * to_unit(block[pair + 1]);
  return radius * ((lane & 1) == 0 ? std::cos(angle) : std::sin(angle));
}

}  // namespace funnel

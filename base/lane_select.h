// c ? a : b for doubles, bit for bit and without a branch, for loops meant to run in SIMD lanes.
// Written as a ternary, GCC turns an arm into a branch when it can (it moves a multiplication
// that only one arm needs into it, since a multiplication may trap) and then will not vectorise
// the loop; a select on the bits it always vectorises (a blend).
#pragma once

#include <bit>
#include <cstdint>

namespace pcbench {

inline double lane_select(bool c, double a, double b) {
  const std::uint64_t mask = -static_cast<std::uint64_t>(c);
  return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & mask) |
                               (std::bit_cast<std::uint64_t>(b) & ~mask));
}

}  // namespace pcbench

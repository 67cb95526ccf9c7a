// cos and sin of a direction's azimuth 2πu for u in [0, 1), as the samplers draw it.
//
// libm's sincos was 6–8% of a render's CPU time (one call per BSDF or emission sample), most of
// it in the general argument reduction. Here the reduction is exact on u itself: 8u splits into
// an octant and a fraction without rounding (u has at most 53 bits, and multiplying by 8 and
// taking the integer part off are exact), so only the angle x = π/4 × fraction in [0, π/4] and
// the series round. The series are Taylor's, cut where the next term is below 2^-53 on [0, π/4]
// (x^17/17! < 5e-17 for sin, x^18/18! < 3e-18 for cos), so their coefficients are 1/n! and
// nothing else: measured against long double, within 1.6 × 2^-53 absolute; against std::cos and
// std::sin of 2πu, within 6.5 × 2^-53 (libm's own argument 2πu rounds first), which
// scene_sampling_test.cpp bounds.
//
// Written without branches or integer conversions, so that a loop of it runs in SIMD lanes
// (cos_sin_of_turns): the octants' choices are selects (each was a coin flip the branch
// predictor lost half the time), and the octant is read off the bits of a double.
#pragma once

#include <bit>
#include <cstdint>
#include <span>

#include "base/lane_select.h"

namespace pcbench::scene {

struct CosSin {
  double cos = 1.0, sin = 0.0;
};

inline CosSin cos_sin_of_turn(double u) {
  const double eighths = 8.0 * u;  // [0, 8)
  // The octant, floor(eighths), exactly: adding 2^52 rounds to the nearest integer (the sum's
  // unit in the last place is 1), one less when that rounded up; its low bits are then the
  // integer's, read from the sum of the octant and 2^52, which is exact.
  const double nearest = (eighths + 0x1p52) - 0x1p52;
  const double whole = nearest - lane_select(nearest > eighths, 1.0, 0.0);
  const std::uint64_t octant = std::bit_cast<std::uint64_t>(whole + 0x1p52) & 7;
  const double past = eighths - whole;  // [0, 1): the angle past the octant's start, in eighths
  // Odd octants count back from their end: the angle is in [0, π/4].
  const double f = lane_select((octant & 1) != 0, 1.0 - past, past);
  const double x = f * 0.78539816339744830962;  // π/4
  const double z = x * x;
  // sin x = x (1 - z/3! + z²/5! - ... - z⁷/15!), cos x = 1 - z/2! + z²/4! - ... + z⁸/16!.
  const double s =
      x + x * z *
              (-1.0 / 6.0 +
               z * (1.0 / 120.0 +
                    z * (-1.0 / 5040.0 +
                         z * (1.0 / 362880.0 +
                              z * (-1.0 / 39916800.0 +
                                   z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0)))))));
  const double c =
      1.0 +
      z * (-0.5 + z * (1.0 / 24.0 +
                       z * (-1.0 / 720.0 +
                            z * (1.0 / 40320.0 + z * (-1.0 / 3628800.0 +
                                                      z * (1.0 / 479001600.0 +
                                                           z * (-1.0 / 87178291200.0 +
                                                                z * (1.0 / 20922789888000.0))))))));
  // The octant's symmetry: θ = π/2 − x, π/2 + x, … swap cos and sin; the signs by quadrant.
  const bool swap = ((octant + 1) & 2) != 0;
  const double cos_abs = lane_select(swap, s, c);
  const double sin_abs = lane_select(swap, c, s);
  return {lane_select(((octant + 2) & 4) != 0, -cos_abs, cos_abs),
          lane_select((octant & 4) != 0, -sin_abs, sin_abs)};
}

// cos_sin_of_turn(u[i]) into cos[i] and sin[i] for every i, bit for bit, in the widest SIMD
// lanes the machine has (turn_trig.cpp): a round of walks samples its azimuths together.
void cos_sin_of_turns(std::span<const double> u, std::span<double> cos, std::span<double> sin);

}  // namespace pcbench::scene

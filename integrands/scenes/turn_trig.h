// cos and sin of a direction's azimuth 2πu for u in [0, 1), as the samplers draw it.
//
// libm's sincos was 6–8% of a render's CPU time (one call per BSDF or emission sample), most of
// it in the general argument reduction. Here the reduction is exact on u itself: 8u splits into
// an octant and a fraction without rounding (u has at most 53 bits, and multiplying by 8 and
// taking the integer part off are exact), so only the kernel polynomials on [0, π/4] round.
// Those are fdlibm's (__kernel_sin, __kernel_cos: minimax, under one ulp on [-π/4, π/4]); the
// result is within a few ulps of std::cos and std::sin of 2πu (scene_sampling_test.cpp checks).
#pragma once

namespace pcbench::scene {

struct CosSin {
  double cos = 1.0, sin = 0.0;
};

inline CosSin cos_sin_of_turn(double u) {
  const double eighths = 8.0 * u;
  const int octant = static_cast<int>(eighths);
  double f = eighths - octant;  // [0, 1): the angle past the octant's start, in eighths of a turn
  if (octant & 1)
    f = 1.0 - f;  // odd octants count back from their end, so the angle is in [0, π/4]
  const double x = f * 0.78539816339744830962;  // π/4
  const double z = x * x;
  // fdlibm's __kernel_sin (S1..S6) and __kernel_cos (C1..C6), without their tail arguments.
  const double sr = 8.33333333332248946124e-03 +
                    z * (-1.98412698298579493134e-04 +
                         z * (2.75573137070700676789e-06 +
                              z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)));
  const double s = x + z * x * (-1.66666666666666324348e-01 + z * sr);
  const double cr =
      z * (4.16666666666666019037e-02 +
           z * (-1.38888888888741095749e-03 +
                z * (2.48015872894767294178e-05 +
                     z * (-2.75573143513906633035e-07 +
                          z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  const double c = w + (((1.0 - w) - hz) + z * cr);
  // The octant's symmetry: θ = π/2 − x, π/2 + x, … swap cos and sin; the signs by quadrant.
  const bool swap = ((octant + 1) & 2) != 0;
  const double cos_abs = swap ? s : c;
  const double sin_abs = swap ? c : s;
  return {((octant + 2) & 4) != 0 ? -cos_abs : cos_abs, (octant & 4) != 0 ? -sin_abs : sin_abs};
}

}  // namespace pcbench::scene

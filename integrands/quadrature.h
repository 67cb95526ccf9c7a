// Adaptive Gauss–Kronrod quadrature for the references that have no closed form (door-2d).
//
// This is the only translation unit of the library that includes Boost.Math's quadrature
// headers: they cost about 2 s of compile time per file.
#pragma once

#include <functional>
#include <span>

namespace pcbench {

struct QuadratureResult {
  double value = 0.0;
  double error = 0.0;  // Boost's estimate of |error|, summed over the pieces
};

// ∫_a^b g(t) dt with the adaptive 31-point Gauss–Kronrod rule on each piece between the sorted
// `breakpoints` that lie in (a, b). Put every kink and jump of g among the breakpoints: on smooth
// pieces the rule converges geometrically.
QuadratureResult integrate_pieces(const std::function<double(double)>& g, double a, double b,
                                  std::span<const double> breakpoints, double relative_tolerance);

}  // namespace pcbench

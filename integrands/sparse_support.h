// sparse-support: f is zero except on a small square of the (x0, y0) plane, as when a small light
// is seen only through a small pixel; 1 + 1 dimensions:
//
//     f(x, y) = 1 + x0 y0   if x0 in [a, a + e] and y0 in [b, b + e],   else 0,
//
// with a = 0.3, b = 0.65 and e = √support, so that f != 0 on a fraction `support` of the domain.
//
// Parameters: support (default 0.0025, range [1e-8, 0.01]): f = 0 on at least 99% of the domain.
//
// Exact value (kExact): I = e² + (e (a + e/2)) (e (b + e/2)), the square's area plus the
// product of the two one-dimensional first moments. At the defaults (e = 0.05):
// I = 0.0025 + 0.01625 · 0.03375 = 0.0030484375.
//
// Sampling: uniform, p(x) = p(y) = 1.
//
// Stresses (tag "stress"): most pairs contribute 0; with a pool of M light paths, every entry can
// have f = 0 for a given y, so an importance-based P must cope with an all-zero pool (the
// estimate is then 0, not 0/0).
#pragma once

#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"

namespace pcbench {

class SparseSupport {
 public:
  static constexpr double kLightStart = 0.3;    // a
  static constexpr double kCameraStart = 0.65;  // b

  static std::vector<ParamSpec> params();
  explicit SparseSupport(const ResolvedParams& params);
  int light_dims() const { return 1; }
  int camera_dims() const { return 1; }
  Reference reference() const;

  double f(const double* x, const double* y) const {
    if (x[0] < kLightStart || x[0] > kLightStart + edge_) return 0.0;
    if (y[0] < kCameraStart || y[0] > kCameraStart + edge_) return 0.0;
    return 1.0 + x[0] * y[0];
  }

  double edge() const { return edge_; }

 private:
  double edge_;  // e
};

}  // namespace pcbench

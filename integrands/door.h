// door: flatland transport through a narrow gap. Light point (x0, 0), camera point (y0, h), a
// wall on the line z = t h with one opening [g - gap/2, g + gap/2]; 1 + 1 dimensions:
//
//     f(x, y) = k(y0 - x0) 1[c in opening],   c = x0 + t (y0 - x0),
//     k(u) = h² / (2 r³),   r² = h² + u²   (the flatland form factor's kernel).
//
// Parameters: distance h (default 1, [0.01, 100]), wall_height t (0.5, a fraction of h,
// [0.01, 0.99]), gap (0.01, [1e-6, 4]), gap_center g (0.4, [0, 1]).
//
// Exact value (kExact): ∫∫ k 1[c in opening] in closed form, parallel::flatland_through (see
// blocker.h for the derivation). At the defaults: I = 0.006246834... (about 1.6% of
// the pairs pass).
//
// Sampling: uniform, p(x) = p(y) = 1.
// approximate_importance(x, y) = k(y0 - x0), the unoccluded kernel (> 0 everywhere).
//
// Stresses: x must pass through a small window to reach y; the unoccluded importance cannot see
// the window, so resampling by it gains little over uniform draws. door-2d is the 2 + 2 version.
#pragma once

#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"
#include "integrands/parallel_geometry.h"

namespace pcbench {

class Door : public parallel::FlatlandInterval {
 public:
  static std::vector<ParamSpec> params();
  explicit Door(const ResolvedParams& params);
  Reference reference() const;

  double f(const double* x, const double* y) const {
    return crosses_interval(x, y) ? approximate_importance(x, y) : 0.0;
  }
};

}  // namespace pcbench

// door-2d: transport between two parallel unit squares through a rectangular opening in a wall
// between them. Light point x on the square at z = 0, camera point y on the square at z = h, a
// wall on the plane z = t h with the opening [g - gap/2, g + gap/2] × [g - len/2, g + len/2];
// 2 + 2 dimensions:
//
//     f(x, y) = h² / (π r⁴) 1[c in opening],   c = x + t (y - x),   r² = h² + |x - y|²
//
// (the form factor's kernel, as in form-factor.h).
//
// Parameters: distance h (default 1, [0.01, 100]), wall_height t (0.5, a fraction of h,
// [0.01, 0.99]), gap (0.02, the opening's width along axis 0, [1e-6, 4]), gap_length len (0.2,
// along axis 1, [1e-6, 4]), gap_center g (0.4, the opening's center on both axes, [0, 1]).
//
// Reference (kNumerical, computed at construction): for fixed x the passing offsets u = y - x form
// a rectangle whose sides depend on x0 and x1 separately (parallel::offsets_through), and the
// kernel's integral over a rectangle of offsets is a closed form (the point-to-rectangle form
// factor, Howell B-3; parallel::rectangle_integral). The remaining 2D integral over x is nested
// adaptive Gauss–Kronrod (31 points, integrands/quadrature.h), split at the kinks of the
// rectangle's sides, where the integrand is smooth; its error estimate is reported as the
// reference's uncertainty only if it exceeds 1e-12 of the value (at the defaults it does not).
// At the defaults: I = 0.001761912...
//
// Sampling: uniform, p(x) = p(y) = 1.
// approximate_importance(x, y) = h² / (π r⁴), the unoccluded kernel (> 0 everywhere).
//
// Stresses: x must pass through a slit to reach y (about 1% of the pairs do at the defaults),
// in more dimensions than door.
#pragma once

#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"
#include "integrands/parallel_geometry.h"

namespace pcbench {

class Door2d {
 public:
  static std::vector<ParamSpec> params();
  explicit Door2d(const ResolvedParams& params);
  int light_dims() const { return 2; }
  int camera_dims() const { return 2; }
  Reference reference() const { return reference_; }

  double f(const double* x, const double* y) const {
    const double c0 = parallel::crossing(x[0], y[0], height_);
    const double c1 = parallel::crossing(x[1], y[1], height_);
    if (c0 < lo_[0] || c0 > hi_[0] || c1 < lo_[1] || c1 > hi_[1]) return 0.0;
    return parallel::kernel_3d(y[0] - x[0], y[1] - x[1], distance_);
  }

  double approximate_importance(const double* x, const double* y) const {
    return parallel::kernel_3d(y[0] - x[0], y[1] - x[1], distance_);
  }

 private:
  Reference compute_reference() const;

  double distance_;
  double height_;  // t
  double lo_[2], hi_[2];
  Reference reference_;
};

}  // namespace pcbench

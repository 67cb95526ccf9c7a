// genz-discontinuous: Genz's discontinuous family (A. Genz, "Testing multidimensional integration
// routines", 1984) over z = (x, y), x in [0,1]^a (light side), y in [0,1]^b (camera side),
// d = a + b:
//
//     f(z) = exp(s Σ_i z_i)   if x0 < c and y0 < c,   else 0.
//
// Genz cuts the first two coordinates; here they are the first coordinate of each side, x0 and y0,
// so that the discontinuity couples the light and the camera path for any a, b >= 1.
//
// Parameters: light_dims a (default 1), camera_dims b (1), sharpness s (4), center c (0.6).
//
// Exact value: a product of one-dimensional integrals, ∫_0^c exp(s t) dt = expm1(s c)/s for x0 and
// y0 and expm1(s)/s for the others: I = (expm1(s c)/s)² (expm1(s)/s)^(d-2). At the defaults
// (d = 2): I = 6.2790... (kExact).
//
// Sampling (non-uniform): every coordinate independently from the truncated exponential density
// with half of f's rate, λ = s/2,
//     p(t) = λ exp(-λ (1 - t)) / (1 - exp(-λ)),   t = 1 + log1p(-(1 - u)(1 - exp(-λ))) / λ,
// by inversion (written so that no exponential overflows); p(x) = Π_i p(x_i), likewise p(y). The
// density follows the growth of f but not its cut: it puts most samples of x0, y0 where f = 0.
//
// Stresses: a jump along x0 = c and y0 = c; f = 0 on 1 - c² of the (x0, y0) square; p != 1.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "base/params.h"
#include "integrands/genz.h"
#include "integrands/integrand.h"

namespace pcbench {

class GenzDiscontinuous : public GenzProductDensity<GenzDiscontinuous> {
 public:
  static std::vector<ParamSpec> params() { return GenzShape::params("4", "0.6"); }
  explicit GenzDiscontinuous(const ResolvedParams& params);
  Reference reference() const;

  double f(const double* x, const double* y) const {
    if (!(x[0] < center_ && y[0] < center_)) return 0.0;
    return std::exp(sharpness_ * coordinate_sum(x, y));
  }

  // The density and its inverse CDF, for GenzProductDensity.
  friend class GenzProductDensity<GenzDiscontinuous>;

 private:
  double coordinate_pdf(double t) const { return rate_ * std::exp(-rate_ * (1.0 - t)) / mass_; }

  double sample_coordinate(double u) const {
    return std::clamp(1.0 + std::log1p(-(1.0 - u) * mass_) / rate_, 0.0, 1.0);
  }

  double rate_;  // λ = s/2
  double mass_;  // 1 - exp(-λ)
};

}  // namespace pcbench

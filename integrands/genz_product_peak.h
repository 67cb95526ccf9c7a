// genz-product-peak: Genz's product peak family (A. Genz, "Testing multidimensional integration
// routines", 1984) over z = (x, y), x in [0,1]^a (light side), y in [0,1]^b (camera side),
// d = a + b:
//
//     f(z) = Π_i (s^-2 + (z_i - c)²)^-1
//
// Parameters: light_dims a (default 1), camera_dims b (1), sharpness s (5), center c (0.4).
//
// Exact value: f is a product, and ∫_0^1 dt / (s^-2 + (t - c)²) = s (atan(s (1 - c)) + atan(s c)),
// so I = [s (atan(s (1 - c)) + atan(s c))]^d. At the defaults (d = 2): I = 138.7913... (kExact).
//
// Sampling: uniform, p(x) = p(y) = 1.
//
// Stresses: a Cauchy-shaped peak of height s² per dimension at z = (c, ..., c); its shoulders are
// heavier than the Gaussian family's, so more of I lies away from the peak.
#pragma once

#include <vector>

#include "base/params.h"
#include "integrands/genz.h"
#include "integrands/integrand.h"

namespace pcbench {

class GenzProductPeak : public GenzShape {
 public:
  static std::vector<ParamSpec> params() { return GenzShape::params("5", "0.4"); }
  explicit GenzProductPeak(const ResolvedParams& params);
  Reference reference() const;

  double f(const double* x, const double* y) const {
    const double width2 = 1.0 / (sharpness_ * sharpness_);
    double product = 1.0;
    for (int i = 0; i < light_dims_; ++i) product *= width2 + (x[i] - center_) * (x[i] - center_);
    for (int i = 0; i < camera_dims_; ++i) product *= width2 + (y[i] - center_) * (y[i] - center_);
    return 1.0 / product;
  }
};

}  // namespace pcbench

// narrow-peak: a near-specular connection. f peaks where the camera point y0 is within a tiny
// width w of the light point x0, as a sharp glossy lobe would; 1 + 1 dimensions:
//
//     f(x, y) = φ_w(y0 - x0) = exp(-(y0 - x0)² / (2 w²)) / (w √(2π))
//
// Parameters: width w (default 1e-4, range [1e-8, 0.1]).
//
// Exact value (kExact): with u = y0 - x0, whose density on the unit square is 1 - |u|,
//     I = ∫_{-1}^{1} (1 - |u|) φ_w(u) du = erf(1/(w √2)) - w √(2/π) (1 - exp(-1/(2 w²))).
// At the defaults: I = 0.99992021...
//
// Sampling: uniform, p(x) = p(y) = 1.
//
// Stresses (tag "stress"): a peak of width 1e-4 that a uniform pair lands within one width of
// with probability ≈ 2 w; ∫∫ f² ≈ 1/(2 w √π) (about 2800 at the defaults) makes plain's
// per-sample variance huge next to I² ≈ 1, while resampling a pool by |f| finds the lobe.
#pragma once

#include <cmath>
#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"

namespace pcbench {

class NarrowPeak {
 public:
  static std::vector<ParamSpec> params();
  explicit NarrowPeak(const ResolvedParams& params);
  int light_dims() const { return 1; }
  int camera_dims() const { return 1; }
  Reference reference() const;

  double f(const double* x, const double* y) const {
    const double z = (y[0] - x[0]) / width_;
    return normalization_ * std::exp(-0.5 * z * z);
  }

 private:
  double width_;
  double normalization_;  // 1 / (w √(2π))
};

}  // namespace pcbench

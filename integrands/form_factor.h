// form-factor: radiative exchange between two directly opposed parallel unit squares at distance
// h, light point x on square A (z = 0), camera point y on square B (z = h), 2 + 2 dimensions:
//
//     f(x, y) = cos θ_x cos θ_y / (π r²) = h² / (π r⁴),   r² = h² + |x - y|²
//
// Parameters: distance h (default 1, range [0.01, 100]).
//
// Exact value: ∫_A ∫_B f = area(A) F_{A->B} = F, the form factor of directly opposed parallel
// rectangles (Howell, "A Catalog of Radiation Heat Transfer Configuration Factors", C-11; Siegel &
// Howell), with X = Y = 1/h; see parallel::square_form_factor. At the defaults: I = 0.1998249...
// (kExact; the closed form loses about log10(h²) digits to cancellation, 4 at h = 100).
//
// Sampling: uniform, p(x) = p(y) = 1.
//
// Stresses: a geometry kernel that couples x and y (the quantity resampling is meant to exploit);
// at small h it is a ridge of height 1/(π h²) and width h along x = y.
#pragma once

#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"
#include "integrands/parallel_geometry.h"

namespace pcbench {

class FormFactor {
 public:
  static std::vector<ParamSpec> params() { return {parallel::distance_param()}; }
  explicit FormFactor(const ResolvedParams& params);
  int light_dims() const { return 2; }
  int camera_dims() const { return 2; }
  Reference reference() const;

  double f(const double* x, const double* y) const {
    return parallel::kernel_3d(y[0] - x[0], y[1] - x[1], distance_);
  }

 private:
  double distance_;
};

}  // namespace pcbench

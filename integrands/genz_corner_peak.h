// genz-corner-peak: Genz's corner peak family (A. Genz, "Testing multidimensional integration
// routines", 1984) over z = (x, y), x in [0,1]^a (light side), y in [0,1]^b (camera side),
// d = a + b, with equal coefficients s:
//
//     f(z) = (1 + s Σ_i z_i)^-(d+1)
//
// Parameters: light_dims a (default 1), camera_dims b (1), sharpness s (1). No center: the peak
// sits at the corner z = 0.
//
// Exact value: I = Π_{k=0}^{d} 1 / (1 + k s) (kExact). Derivation: integrating one coordinate at a
// time gives the textbook alternating sum over the cube's vertices,
//     I = 1/(d! s^d) Σ_{k=0}^{d} (-1)^k C(d, k) / (1 + k s),
// which is the d-th forward difference of g(k) = 1/(1 + k s), and Δ^d g(0) = (-1)^d d! s^d /
// Π_{k=0}^{d} (1 + k s) (induction on d, or partial fractions of 1/Π(1 + k s)). The sum cancels
// catastrophically (terms of size C(d, d/2) for a result of 1/Π(1 + k s)): by d ≈ 15 it keeps no
// correct digit in double precision, while the product keeps all of them (d + 1 roundings).
// At the defaults (d = 2): I = 1/6.
//
// Sampling: uniform, p(x) = p(y) = 1.
//
// Stresses: the value is concentrated at one corner of the cube and falls polynomially; the
// reference formula's stability in high dimension (a test checks d = 20 against 50-digit
// arithmetic).
#pragma once

#include <cmath>
#include <vector>

#include "base/params.h"
#include "integrands/genz.h"
#include "integrands/integrand.h"

namespace pcbench {

class GenzCornerPeak : public GenzShape {
 public:
  static std::vector<ParamSpec> params() { return GenzShape::params("1"); }
  using GenzShape::GenzShape;
  Reference reference() const;

  double f(const double* x, const double* y) const {
    return std::pow(1.0 + sharpness_ * coordinate_sum(x, y), -(dims() + 1));
  }
};

}  // namespace pcbench

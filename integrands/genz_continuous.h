// genz-continuous: Genz's continuous family (A. Genz, "Testing multidimensional integration
// routines", 1984) over z = (x, y), x in [0,1]^a (light side), y in [0,1]^b (camera side),
// d = a + b:
//
//     f(z) = exp(-s Σ_i |z_i - c|)
//
// Parameters: light_dims a (default 1), camera_dims b (1), sharpness s (5), center c (0.4).
//
// Exact value: f is a product, and ∫_0^1 exp(-s |t - c|) dt = (2 - exp(-s c) - exp(-s (1 - c))) / s
// (computed with expm1), so I = that to the power d. At the defaults (d = 2): I = 0.1317512...
// (kExact).
//
// Sampling (non-uniform): every coordinate of x and of y independently from the truncated Laplace
// density with half of f's rate, λ = s/2:
//     p(t) = exp(-λ |t - c|) / Z,   Z = (2 - exp(-λ c) - exp(-λ (1 - c))) / λ,
// by inverting its CDF piece by piece (left and right of c); p(x) = Π_i p(x_i), likewise p(y).
// With half the rate, f/p still peaks at c (plain is not zero-variance), and
// ∫ f²/p = Π_i Z ∫ exp(-(2s - λ) |t - c|) dt stays a closed form for variance checks.
//
// Stresses: a kink (not a jump) at c in every dimension; p(x), p(y) != 1, so a wrong pdf shows up
// as bias.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "base/params.h"
#include "integrands/genz.h"
#include "integrands/integrand.h"

namespace pcbench {

class GenzContinuous : public GenzProductDensity<GenzContinuous> {
 public:
  static std::vector<ParamSpec> params() { return GenzShape::params("5", "0.4"); }
  explicit GenzContinuous(const ResolvedParams& params);
  Reference reference() const;

  double f(const double* x, const double* y) const {
    double distance = 0.0;
    for (int i = 0; i < light_dims_; ++i) distance += std::fabs(x[i] - center_);
    for (int i = 0; i < camera_dims_; ++i) distance += std::fabs(y[i] - center_);
    return std::exp(-sharpness_ * distance);
  }

  // The density and its inverse CDF, for GenzProductDensity.
  friend class GenzProductDensity<GenzContinuous>;

 private:
  double coordinate_pdf(double t) const {
    return std::exp(-rate_ * std::fabs(t - center_)) / mass_;
  }

  // Inverse CDF: the mass left of c is left_mass_, the rest lies right of c.
  double sample_coordinate(double u) const {
    const double m = u * mass_;
    const double t = m < left_mass_ ? center_ + std::log1p(rate_ * m + left_offset_) / rate_
                                    : center_ - std::log1p(-rate_ * (m - left_mass_)) / rate_;
    return std::clamp(t, 0.0, 1.0);
  }

  double rate_;         // λ = s/2
  double left_offset_;  // expm1(-λ c), once rather than per sample left of c
  double left_mass_;    // ∫_0^c exp(-λ (c - t)) dt = -left_offset_ / λ
  double mass_;         // Z
};

}  // namespace pcbench

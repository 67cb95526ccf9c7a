// wide-range: resampling importances spanning 1e-300 .. 1e300, and f itself from about 1e-3 to
// 1e300, while f / (p(x) p(y)) stays within [1, 2]; 1 + 1 dimensions. The light and camera
// densities are the integrand's own:
//
//     f(x, y) = ρ(x0) σ(y0) (1 + a(x0) b(y0)),        λ = D ln 10,
//     ρ(x0) = 1 / (λ x0) on [10^-D, 1] (log-uniform),  a(x0) = -ln(x0) / λ,
//     σ(y0) = λ e^(-λ y0) / (1 - e^(-λ)) on [0, 1],    b(y0) = (1 - e^(-λ y0)) / (1 - e^(-λ)),
//
// and f = 0 for x0 < 10^-D (where ρ = 0). a is 1 - the CDF of ρ and b the CDF of σ.
//
// Parameters: decades D (default 300, range [1, 307]).
//
// Exact value (kExact): under x0 ~ ρ and y0 ~ σ, a(x0) and b(y0) are independent Uniform(0, 1)
// (probability integral transform), so I = E[1 + a b] = 1 + 1/4 = 5/4 for every D.
//
// Sampling (non-uniform, by inversion): x0 = e^(-λ t), p(x) = ρ(x0); y0 = -log1p(-v (1 - e^(-λ)))
// / λ, p(y) = σ(y0), with t, v uniform.
//
// Approximate importance: (1 + a b) 10^(D (2 b - 1)). Within one pool (one y) it is proportional
// to f / p(x), the variance-optimal P; its scale 10^(D (2 b - 1)) depends on y alone, so it
// cancels from P in exact arithmetic, and spans 10^-D .. 10^D evenly across camera samples (b is
// uniform). importance=f instead spans 10^D / λ .. 1/λ inside one pool (ρ is log-uniform).
//
// Stresses (tag "stress"): the resampling step's normaliser Σ w. At D = 307 the approximate
// importances of a pool sum beyond DBL_MAX for camera samples with b near 1 (any M >= 16), and
// so do |f| for pools of about 10^4; at D = 12 the importance ratios across a pool reach 1e12.
#pragma once

#include <cmath>
#include <vector>

#include "base/params.h"
#include "base/rng.h"
#include "integrands/integrand.h"

namespace pcbench {

class WideRange {
 public:
  static std::vector<ParamSpec> params();
  explicit WideRange(const ResolvedParams& params);
  int light_dims() const { return 1; }
  int camera_dims() const { return 1; }
  Reference reference() const { return {.value = 1.25, .kind = ReferenceKind::kExact}; }

  double f(const double* x, const double* y) const {
    if (!(x[0] >= light_floor_)) return 0.0;
    return light_pdf(x) * camera_pdf(y) * (1.0 + light_rank(x[0]) * camera_rank(y[0]));
  }
  double approximate_importance(const double* x, const double* y) const {
    const double b = camera_rank(y[0]);
    return (1.0 + light_rank(x[0]) * b) * std::exp(rate_ * (2.0 * b - 1.0));
  }

  double sample_light(RandomStream& rng, double* x) const {
    x[0] = std::exp(-rate_ * rng.uniform());
    return light_pdf(x);
  }
  double sample_camera(RandomStream& rng, double* y) const {
    y[0] = -std::log1p(-rng.uniform() * camera_mass_) / rate_;
    return camera_pdf(y);
  }
  double light_pdf(const double* x) const {
    return x[0] >= light_floor_ ? 1.0 / (rate_ * x[0]) : 0;
  }
  double camera_pdf(const double* y) const {
    return y[0] >= 0.0 && y[0] <= 1.0 ? rate_ * std::exp(-rate_ * y[0]) / camera_mass_ : 0.0;
  }
  // a(x0) and b(y0): Uniform(0, 1) under the sampling densities.
  double light_rank(double x0) const { return -std::log(x0) / rate_; }
  double camera_rank(double y0) const { return std::expm1(-rate_ * y0) / -camera_mass_; }

 private:
  double rate_;         // λ = D ln 10
  double light_floor_;  // 10^-D = e^-λ
  double camera_mass_;  // 1 - e^-λ
};

}  // namespace pcbench

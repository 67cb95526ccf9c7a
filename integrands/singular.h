// singular-finite, singular-infinite: a singularity along the diagonal x0 = y0, like the 1/r²
// of two surfaces that touch; 1 + 1 dimensions:
//
//     f(x, y) = |x0 - y0|^-α
//
// One model, two registry entries that differ in the range of α:
//   singular-finite    exponent α (default 0.3, range [0, 0.45]): finite variance, since
//                      ∫∫ f² = ∫ 2 (1 - u) u^-2α du is finite for α < 1/2;
//   singular-infinite  exponent α (default 0.75, range [0.5, 0.95]): finite mean, infinite
//                      variance (∫ u^-1.5 diverges at 0).
// Under uniform sampling P(f > t) = P(|x0 - y0| < t^(-1/α)) ~ 2 t^(-1/α): a Pareto tail of index
// 1/α, 3.3 for the finite member and 1.33 for the infinite one (far apart, on both sides of 2).
//
// Exact value (kExact): with u = |x0 - y0|, of density 2 (1 - u) on [0, 1],
//     I = ∫_0^1 2 (1 - u) u^-α du = 2 / ((1 - α)(2 - α)).
// At the defaults: 1.680672... (α = 0.3) and 6.4 (α = 0.75).
//
// Sampling: uniform, p(x) = p(y) = 1.
//
// Stresses (tags "stress"; "infinite-variance" for the second): heavy tails. For the infinite
// member a t-test across replicates has no valid standard error; the verifier should flag the
// tail rather than pass or fail the mean.
#pragma once

#include <cmath>
#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"

namespace pcbench {

class DiagonalSingularity {
 public:
  explicit DiagonalSingularity(const ResolvedParams& params);
  int light_dims() const { return 1; }
  int camera_dims() const { return 1; }
  Reference reference() const;

  double f(const double* x, const double* y) const {
    return std::pow(std::fabs(x[0] - y[0]), -exponent_);
  }

 private:
  double exponent_;  // α
};

class SingularFinite : public DiagonalSingularity {
 public:
  static std::vector<ParamSpec> params();
  using DiagonalSingularity::DiagonalSingularity;
};

class SingularInfinite : public DiagonalSingularity {
 public:
  static std::vector<ParamSpec> params();
  using DiagonalSingularity::DiagonalSingularity;
};

}  // namespace pcbench

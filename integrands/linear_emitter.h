// linear-emitter: the form-factor geometry with an emitter whose radiance grows linearly across
// the light square, sampled in proportion to it (emission sampling). 2 + 2 dimensions:
//
//     f(x, y) = L(x) h² / (π r⁴),   L(x) = 2 x0,   r² = h² + |x - y|²
//
// Parameters: distance h (default 1, range [0.01, 100]).
//
// Exact value: I = F, the form factor of form-factor.h (kExact). Reflecting both squares,
// (x0, y0) -> (1 - x0, 1 - y0), leaves the kernel unchanged, so ∫∫ x0 k = ∫∫ (1 - x0) k = F/2.
// At the defaults: I = 0.1998249...
//
// Sampling (non-uniform, light side): p(x) = 2 x0 (x1 uniform), by inversion x0 = √(1 - u), which
// is never 0, so p(x) > 0 on every sample; the camera side is uniform, p(y) = 1. Then f/p is the
// bounded kernel, as in a renderer that samples emitters by power.
//
// Stresses: a linear density by inversion on a transport kernel; an estimator that forgets to
// divide by p(x), or divides by the wrong one, is biased by a factor that varies with x0.
#pragma once

#include <cmath>
#include <vector>

#include "base/params.h"
#include "base/rng.h"
#include "integrands/integrand.h"
#include "integrands/parallel_geometry.h"

namespace pcbench {

class LinearEmitter {
 public:
  static std::vector<ParamSpec> params() { return {parallel::distance_param()}; }
  explicit LinearEmitter(const ResolvedParams& params);
  int light_dims() const { return 2; }
  int camera_dims() const { return 2; }
  Reference reference() const;

  double f(const double* x, const double* y) const {
    return 2.0 * x[0] * parallel::kernel_3d(y[0] - x[0], y[1] - x[1], distance_);
  }

  double sample_light(RandomStream& rng, double* x) const {
    x[0] = std::sqrt(1.0 - rng.uniform());
    x[1] = rng.uniform();
    return light_pdf(x);
  }
  double light_pdf(const double* x) const { return 2.0 * x[0]; }

 private:
  double distance_;
};

}  // namespace pcbench

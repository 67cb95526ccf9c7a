// Genz's test families (A. Genz, "Testing multidimensional integration routines", 1984) with the
// dimensions split between the light side x in [0,1]^a and the camera side y in [0,1]^b.
// z = (x, y) is the concatenated point, d = a + b. Sampling is uniform: p(x) = p(y) = 1.
//
// Parameters of every family: light_dims (a), camera_dims (b), sharpness (Genz's difficulty s,
// the same in every dimension), center (Genz's shift c; the corner peak has none).
//
// The other four families, one file each: genz_product_peak.h, genz_corner_peak.h,
// genz_continuous.h, genz_discontinuous.h.
#pragma once

#include <cmath>
#include <vector>

#include "base/params.h"
#include "base/rng.h"
#include "integrands/integrand.h"

namespace pcbench {

// What all Genz families share: dimensions, s and c.
class GenzShape {
 public:
  explicit GenzShape(const ResolvedParams& params);
  // center_default == nullptr: the family has no shift c (center_ is then 0).
  static std::vector<ParamSpec> params(const char* sharpness_default,
                                       const char* center_default = nullptr);

  int light_dims() const { return light_dims_; }
  int camera_dims() const { return camera_dims_; }

 protected:
  int dims() const { return light_dims_ + camera_dims_; }
  // Σ_i z_i over z = (x, y).
  double coordinate_sum(const double* x, const double* y) const {
    double sum = 0.0;
    for (int i = 0; i < light_dims_; ++i) sum += x[i];
    for (int i = 0; i < camera_dims_; ++i) sum += y[i];
    return sum;
  }

  int light_dims_;
  int camera_dims_;
  double sharpness_;
  double center_;
};

// A Genz family sampled coordinate by coordinate from one density on [0,1], light side and
// camera side alike: p(x) = Π_i p(x_i), likewise p(y). Derived gives the density
// (`coordinate_pdf(t)`) and its inverse CDF (`sample_coordinate(u)`).
template <class Derived>
class GenzProductDensity : public GenzShape {
 public:
  using GenzShape::GenzShape;

  double sample_light(RandomStream& rng, double* x) const { return sample(rng, x, light_dims_); }
  double sample_camera(RandomStream& rng, double* y) const { return sample(rng, y, camera_dims_); }
  double light_pdf(const double* x) const { return pdf(x, light_dims_); }
  double camera_pdf(const double* y) const { return pdf(y, camera_dims_); }

 private:
  const Derived& density() const { return static_cast<const Derived&>(*this); }

  double sample(RandomStream& rng, double* z, int dims) const {
    for (int i = 0; i < dims; ++i) z[i] = density().sample_coordinate(rng.uniform());
    return pdf(z, dims);
  }

  double pdf(const double* z, int dims) const {
    double product = 1.0;
    for (int i = 0; i < dims; ++i) product *= density().coordinate_pdf(z[i]);
    return product;
  }
};

// genz-gaussian: f(z) = exp(-Σ_i s² (z_i - c)²).
// I = Π_i (√π / (2 s)) (erf(s (1 - c)) + erf(s c)), a product of one-dimensional closed forms.
class GenzGaussian : public GenzShape {
 public:
  static std::vector<ParamSpec> params() { return GenzShape::params("4", "0.5"); }
  using GenzShape::GenzShape;
  Reference reference() const;

  double f(const double* x, const double* y) const {
    double exponent = 0.0;
    for (int i = 0; i < light_dims_; ++i) exponent += (x[i] - center_) * (x[i] - center_);
    for (int i = 0; i < camera_dims_; ++i) exponent += (y[i] - center_) * (y[i] - center_);
    return std::exp(-sharpness_ * sharpness_ * exponent);
  }
};

// genz-oscillatory: f(z) = cos(2π c + s Σ_i z_i).
// I = Re[exp(i 2π c) ((exp(i s) - 1) / (i s))^d], from ∫_0^1 exp(i s t) dt = (exp(i s) - 1)/(i s).
class GenzOscillatory : public GenzShape {
 public:
  static std::vector<ParamSpec> params() { return GenzShape::params("3", "0.25"); }
  using GenzShape::GenzShape;
  Reference reference() const;

  double f(const double* x, const double* y) const {
    return std::cos(kTwoPi * center_ + sharpness_ * coordinate_sum(x, y));
  }

 private:
  static constexpr double kTwoPi = 6.283185307179586476925286766559;
};

}  // namespace pcbench

#include "integrands/genz.h"

#include <cmath>
#include <complex>

#include "integrands/point_integrand.h"

namespace pcbench {

GenzShape::GenzShape(const ResolvedParams& params)
    : light_dims_(static_cast<int>(params.integer("light_dims"))),
      camera_dims_(static_cast<int>(params.integer("camera_dims"))),
      sharpness_(params.real("sharpness")),
      center_(params.has("center") ? params.real("center") : 0.0) {}

std::vector<ParamSpec> GenzShape::params(const char* sharpness_default,
                                         const char* center_default) {
  std::vector<ParamSpec> specs = point_dimension_params();
  specs.push_back({.name = "sharpness",
                   .type = ParamType::kReal,
                   .default_value = sharpness_default,
                   .description = "Genz difficulty s, the same in every dimension",
                   .min = 1e-6,
                   .max = 1e6});
  if (center_default == nullptr) return specs;
  specs.push_back({.name = "center",
                   .type = ParamType::kReal,
                   .default_value = center_default,
                   .description = "Genz shift c",
                   .min = 0,
                   .max = 1});
  return specs;
}

Reference GenzGaussian::reference() const {
  const double s = sharpness_;
  const double one_dim =
      std::sqrt(M_PI) / (2.0 * s) * (std::erf(s * (1.0 - center_)) + std::erf(s * center_));
  return {.value = std::pow(one_dim, dims()), .kind = ReferenceKind::kExact};
}

Reference GenzOscillatory::reference() const {
  using Complex = std::complex<double>;
  const Complex i(0.0, 1.0);
  const Complex one_dim = (std::exp(i * sharpness_) - 1.0) / (i * sharpness_);
  const Complex total = std::exp(i * (kTwoPi * center_)) * std::pow(one_dim, dims());
  return {.value = total.real(), .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

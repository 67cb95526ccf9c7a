#include "integrands/genz.h"

#include <cmath>
#include <complex>

namespace pcbench {
namespace {

std::vector<ParamSpec> genz_params(const char* sharpness_default, const char* center_default) {
  return {
      {.name = "light_dims",
       .type = ParamType::kInt,
       .default_value = "1",
       .description = "dimensions of x (the light side)",
       .min = 1,
       .max = 32},
      {.name = "camera_dims",
       .type = ParamType::kInt,
       .default_value = "1",
       .description = "dimensions of y (the camera side)",
       .min = 1,
       .max = 32},
      {.name = "sharpness",
       .type = ParamType::kReal,
       .default_value = sharpness_default,
       .description = "Genz difficulty s, the same in every dimension",
       .min = 1e-6,
       .max = 1e6},
      {.name = "center",
       .type = ParamType::kReal,
       .default_value = center_default,
       .description = "Genz shift c",
       .min = 0,
       .max = 1},
  };
}

}  // namespace

std::vector<ParamSpec> GenzGaussian::params() {
  return genz_params("4", "0.5");
}

GenzGaussian::GenzGaussian(const ResolvedParams& params)
    : light_dims_(static_cast<int>(params.integer("light_dims"))),
      camera_dims_(static_cast<int>(params.integer("camera_dims"))),
      sharpness_(params.real("sharpness")),
      center_(params.real("center")) {}

Reference GenzGaussian::reference() const {
  const double s = sharpness_;
  const double one_dim =
      std::sqrt(M_PI) / (2.0 * s) * (std::erf(s * (1.0 - center_)) + std::erf(s * center_));
  return {.value = std::pow(one_dim, light_dims_ + camera_dims_), .kind = ReferenceKind::kExact};
}

std::vector<ParamSpec> GenzOscillatory::params() {
  return genz_params("3", "0.25");
}

GenzOscillatory::GenzOscillatory(const ResolvedParams& params)
    : light_dims_(static_cast<int>(params.integer("light_dims"))),
      camera_dims_(static_cast<int>(params.integer("camera_dims"))),
      sharpness_(params.real("sharpness")),
      center_(params.real("center")) {}

Reference GenzOscillatory::reference() const {
  using Complex = std::complex<double>;
  const Complex i(0.0, 1.0);
  const Complex one_dim = (std::exp(i * sharpness_) - 1.0) / (i * sharpness_);
  const Complex total =
      std::exp(i * (kTwoPi * center_)) * std::pow(one_dim, light_dims_ + camera_dims_);
  return {.value = total.real(), .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

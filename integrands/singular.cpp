#include "integrands/singular.h"

namespace pcbench {

DiagonalSingularity::DiagonalSingularity(const ResolvedParams& params)
    : exponent_(params.real("exponent")) {}

Reference DiagonalSingularity::reference() const {
  const double a = exponent_;
  return {.value = 2.0 / ((1.0 - a) * (2.0 - a)), .kind = ReferenceKind::kExact};
}

std::vector<ParamSpec> SingularFinite::params() {
  return {{.name = "exponent",
           .type = ParamType::kReal,
           .default_value = "0.3",
           .description = "α in |x0 - y0|^-α; below 1/2, so the variance is finite",
           .min = 0,
           .max = 0.45}};
}

std::vector<ParamSpec> SingularInfinite::params() {
  return {{.name = "exponent",
           .type = ParamType::kReal,
           .default_value = "0.75",
           .description = "α in |x0 - y0|^-α; in [1/2, 1), so the mean is finite, the variance not",
           .min = 0.5,
           .max = 0.95}};
}

}  // namespace pcbench

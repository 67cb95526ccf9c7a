#include "integrands/genz_discontinuous.h"

#include <fmt/format.h>

#include <cmath>

#include "base/errors.h"

namespace pcbench {

GenzDiscontinuous::GenzDiscontinuous(const ResolvedParams& params)
    : GenzProductDensity(params), rate_(0.5 * sharpness_), mass_(-std::expm1(-rate_)) {
  // The largest value, exp(s d) at z = (1, ..., 1) minus the cut, must be a double.
  if (!(sharpness_ * dims() < 700.0)) {
    throw InputError(fmt::format(
        "integrand 'genz-discontinuous': exp(s d) = exp({} * {}) overflows; lower sharpness",
        sharpness_, dims()));
  }
}

Reference GenzDiscontinuous::reference() const {
  const double s = sharpness_;
  const double cut = std::expm1(s * center_) / s;
  const double full = std::expm1(s) / s;
  return {.value = cut * cut * std::pow(full, dims() - 2), .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

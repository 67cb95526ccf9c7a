#include "integrands/narrow_peak.h"

namespace pcbench {

std::vector<ParamSpec> NarrowPeak::params() {
  return {{.name = "width",
           .type = ParamType::kReal,
           .default_value = "1e-4",
           .description = "standard deviation w of the peak in y0 - x0",
           .min = 1e-8,
           .max = 0.1}};
}

NarrowPeak::NarrowPeak(const ResolvedParams& params)
    : width_(params.real("width")), normalization_(1.0 / (width_ * std::sqrt(2.0 * M_PI))) {}

Reference NarrowPeak::reference() const {
  const double w = width_;
  const double value =
      std::erf(1.0 / (w * M_SQRT2)) + w * std::sqrt(2.0 / M_PI) * std::expm1(-1.0 / (2.0 * w * w));
  return {.value = value, .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

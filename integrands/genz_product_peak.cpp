#include "integrands/genz_product_peak.h"

#include <fmt/format.h>

#include <cmath>

#include "base/errors.h"

namespace pcbench {

GenzProductPeak::GenzProductPeak(const ResolvedParams& params) : GenzShape(params) {
  // The peak value s^(2d) must be a double, or f and I overflow.
  if (!(2.0 * dims() * std::log(sharpness_) < 700.0)) {
    throw InputError(fmt::format(
        "integrand 'genz-product-peak': the peak s^(2d) = {}^{} overflows; lower sharpness",
        sharpness_, 2 * dims()));
  }
}

Reference GenzProductPeak::reference() const {
  const double s = sharpness_;
  const double one_dim = s * (std::atan(s * (1.0 - center_)) + std::atan(s * center_));
  return {.value = std::pow(one_dim, dims()), .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

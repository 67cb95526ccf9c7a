#include "integrands/genz_continuous.h"

#include <cmath>

namespace pcbench {
namespace {

// ∫_0^1 exp(-k |t - c|) dt without cancellation for small k.
double laplace_mass(double k, double c) {
  return -(std::expm1(-k * c) + std::expm1(-k * (1.0 - c))) / k;
}

}  // namespace

GenzContinuous::GenzContinuous(const ResolvedParams& params)
    : GenzProductDensity(params),
      rate_(0.5 * sharpness_),
      left_offset_(std::expm1(-rate_ * center_)),
      left_mass_(-left_offset_ / rate_),
      mass_(laplace_mass(rate_, center_)) {}

Reference GenzContinuous::reference() const {
  return {.value = std::pow(laplace_mass(sharpness_, center_), dims()),
          .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

#include "integrands/wide_range.h"

namespace pcbench {

std::vector<ParamSpec> WideRange::params() {
  return {{.name = "decades",
           .type = ParamType::kReal,
           .default_value = "300",
           .description = "D: f and its importance span 10^-D .. 2 × 10^D",
           .min = 1,
           .max = 307}};
}

WideRange::WideRange(const ResolvedParams& params)
    : rate_(params.real("decades") * std::log(10.0)),
      light_floor_(std::exp(-rate_)),
      camera_mass_(-std::expm1(-rate_)) {}

}  // namespace pcbench

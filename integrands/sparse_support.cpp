#include "integrands/sparse_support.h"

#include <cmath>

namespace pcbench {

std::vector<ParamSpec> SparseSupport::params() {
  return {{.name = "support",
           .type = ParamType::kReal,
           .default_value = "0.0025",
           .description = "fraction of the (x0, y0) square where f != 0",
           .min = 1e-8,
           .max = 0.01}};
}

SparseSupport::SparseSupport(const ResolvedParams& params)
    : edge_(std::sqrt(params.real("support"))) {}

Reference SparseSupport::reference() const {
  const double e = edge_;
  const double light_moment = e * (kLightStart + 0.5 * e);
  const double camera_moment = e * (kCameraStart + 0.5 * e);
  return {.value = e * e + light_moment * camera_moment, .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

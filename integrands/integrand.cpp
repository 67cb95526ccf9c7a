#include "integrands/integrand.h"

#include <cmath>
#include <stdexcept>

namespace pcbench {

const char* to_string(ReferenceKind kind) {
  switch (kind) {
    case ReferenceKind::kExact:
      return "exact";
    case ReferenceKind::kNumerical:
      return "numerical";
    case ReferenceKind::kRendered:
      return "rendered";
    case ReferenceKind::kNone:
      return "none";
  }
  return "none";
}

void PathWorkspace::importance(std::span<const PathPair> pairs, std::span<double> values) {
  connect(pairs, values);
  for (double& v : values) v = std::fabs(v);
}

void PathWorkspace::add_cache_points(std::uint32_t) {
  throw std::runtime_error("this integrand has no cache points (importance=cached)");
}

std::vector<double> PathWorkspace::coordinates(PathSide, std::uint32_t) const {
  return {};
}

bool PathWorkspace::tally_every_path(const StreamId&, const StreamId&, std::uint32_t, std::uint32_t,
                                     std::uint32_t, double, Tally&, CompensatedSum&) {
  return false;
}

}  // namespace pcbench

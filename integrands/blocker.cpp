#include "integrands/blocker.h"

namespace pcbench {

std::vector<ParamSpec> Blocker::params() {
  return {parallel::distance_param(),
          parallel::height_param("strip_height",
                                 "height of the occluding strip, as a fraction t "
                                 "of the distance"),
          parallel::length_param("strip_center", "center of the occluding strip", "0.6", 0, 1),
          parallel::length_param("strip_width", "width of the occluding strip", "0.4", 0, 2)};
}

Blocker::Blocker(const ResolvedParams& params)
    : FlatlandInterval(params.real("distance"), params.real("strip_height"),
                       params.real("strip_center") - 0.5 * params.real("strip_width"),
                       params.real("strip_center") + 0.5 * params.real("strip_width")) {}

Reference Blocker::reference() const {
  return {.value = parallel::flatland_total(distance_) - through_interval(),
          .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

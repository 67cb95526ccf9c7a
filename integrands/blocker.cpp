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
    : distance_(params.real("distance")),
      height_(params.real("strip_height")),
      strip_lo_(params.real("strip_center") - 0.5 * params.real("strip_width")),
      strip_hi_(params.real("strip_center") + 0.5 * params.real("strip_width")) {}

Reference Blocker::reference() const {
  const double blocked = parallel::flatland_through(distance_, height_, strip_lo_, strip_hi_);
  return {.value = parallel::flatland_total(distance_) - blocked, .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

#include "integrands/door.h"

namespace pcbench {

std::vector<ParamSpec> Door::params() {
  return {parallel::distance_param(),
          parallel::height_param("wall_height",
                                 "height of the wall, as a fraction t of the "
                                 "distance"),
          parallel::length_param("gap", "width of the opening in the wall", "0.01", 1e-6, 4),
          parallel::length_param("gap_center", "center of the opening", "0.4", 0, 1)};
}

Door::Door(const ResolvedParams& params)
    : FlatlandInterval(params.real("distance"), params.real("wall_height"),
                       params.real("gap_center") - 0.5 * params.real("gap"),
                       params.real("gap_center") + 0.5 * params.real("gap")) {}

Reference Door::reference() const {
  return {.value = through_interval(), .kind = ReferenceKind::kExact};
}

}  // namespace pcbench

#include "integrands/point_integrand.h"

namespace pcbench {

std::vector<ParamSpec> point_dimension_params() {
  return {{.name = "light_dims",
           .type = ParamType::kInt,
           .default_value = "1",
           .description = "dimensions of x (the light side)",
           .min = 1,
           .max = 32},
          {.name = "camera_dims",
           .type = ParamType::kInt,
           .default_value = "1",
           .description = "dimensions of y (the camera side)",
           .min = 1,
           .max = 32}};
}

}  // namespace pcbench

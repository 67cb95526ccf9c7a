#include "estimators/scene/scene_form.h"

#include <string>

#include "estimators/scene/scene_estimators.h"

namespace pcbench {

EstimatorEntry scene_only_entry(std::string name, std::string description, SceneForm form,
                                bool biased) {
  return {.name = std::move(name),
          .description = std::move(description),
          .biased = biased,
          .params = {},
          .make = {},
          .declared = {},
          .scene_params = std::move(form.params),
          .make_render = std::move(form.make)};
}

ParamSpec light_paths_spec(std::uint32_t default_value) {
  return {.name = "M",
          .type = ParamType::kInt,
          .default_value = std::to_string(default_value),
          .description = "light paths per iteration, shared by every pixel",
          .min = 1,
          .max = 1 << 20};
}

ParamSpec vertex_draws_spec(std::uint32_t default_value) {
  return {.name = "K",
          .type = ParamType::kInt,
          .default_value = std::to_string(default_value),
          .description = "light vertices drawn per camera vertex",
          .min = 1,
          .max = 1024};
}

ParamSpec tile_spec(std::uint32_t default_value) {
  return {.name = "tile",
          .type = ParamType::kInt,
          .default_value = std::to_string(default_value),
          .description = "pixels per side of a screen tile sharing one importance cache point",
          .min = 1,
          .max = 8192};
}

}  // namespace pcbench

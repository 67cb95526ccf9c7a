// An estimator's scene form: the parameters it reads on a scene and the factory of its
// SceneEstimator, given in its registry row (estimators/registry.h) beside its analytic form.
// Also the parameter declarations several scene estimators share; each estimator passes its own
// default, so that its defaults are in its own file.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "base/params.h"
#include "estimators/scene/scene_estimator.h"

namespace pcbench {

using MakeSceneEstimator =
    std::function<std::shared_ptr<const scene::SceneEstimator>(const ResolvedParams&)>;

struct SceneForm {
  std::vector<ParamSpec> params = {};
  MakeSceneEstimator make = {};
};

// M: light paths per iteration, shared by every pixel.
ParamSpec light_paths_spec(std::uint32_t default_value);
// K: light vertices drawn per camera vertex.
ParamSpec vertex_draws_spec(std::uint32_t default_value);
// tile: pixels per side of a screen tile sharing one importance cache point.
ParamSpec tile_spec(std::uint32_t default_value);

}  // namespace pcbench

#include "estimators/ris.h"

#include "estimators/family_params.h"
#include "estimators/reservoir_params.h"
#include "estimators/scene/ris.h"

namespace pcbench {

EstimatorEntry ris_entry() {
  ParamSpec reservoirs = draws_spec(1);
  reservoirs.description = "independent reservoirs per camera sample (draws with replacement)";
  EstimatorEntry entry =
      reservoir_entry("ris",
                      "resampled importance sampling: M candidates from q streamed through a "
                      "reservoir, w = p̂/q, W = Σw / (M p̂)",
                      {pool_size_spec(), reservoirs, target_spec(), pool_mode_spec()}, {});
  SceneForm scene_form = ris_scene_form();
  entry.scene_params = std::move(scene_form.params);
  entry.make_render = std::move(scene_form.make);
  // The furnace renders: the default target, and the one with visibility.
  entry.scene_tests.renders = {{"target=unshadowed", {}},
                               {"target=visible", {{"target", "visible"}}}};
  return entry;
}

}  // namespace pcbench

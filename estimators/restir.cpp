#include "estimators/restir.h"

#include "estimators/family_params.h"
#include "estimators/reservoir_params.h"
#include "estimators/scene/restir.h"

namespace pcbench {

EstimatorEntry restir_entry() {
  EstimatorEntry entry =
      reservoir_entry("restir",
                      "RIS with spatial reuse from N camera samples of the batch sharing one pool, "
                      "weights balance, pairwise or count (generalized RIS)",
                      {pool_size_spec(16, 1, kReuseMaxM), neighbours_spec(), rounds_spec(),
                       target_spec(), reuse_weights_spec()},
                      {.pool = PoolMode::kShared, .neighbours = 4, .rounds = 1});
  SceneForm scene_form = restir_scene_form();
  entry.scene_params = std::move(scene_form.params);
  entry.make_render = std::move(scene_form.make);
  // The furnace renders: each weighting, visible targets, and one round from more neighbours
  // than an 8×8 image's disk holds apart.
  entry.scene_tests.renders = {
      {"weights=balance", {}},
      {"weights=pairwise", {{"weights", "pairwise"}}},
      {"weights=count", {{"weights", "count"}}},
      {"target=visible", {{"target", "visible"}}},
      {"N=16 rounds=1 radius=3", {{"N", "16"}, {"rounds", "1"}, {"radius", "3"}}}};
  return entry;
}

}  // namespace pcbench

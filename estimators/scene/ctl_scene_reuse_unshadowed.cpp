// ctl-scene-reuse-unshadowed (scene negative control): restir (restir.cpp) with visible targets
// whose balance weights see every source's target without visibility.
//
// The mistake: the reservoirs' targets see visibility, so a neighbour in shadow never holds a
// point on the light that the reusing pixel sees; its unshadowed target at that point is still
// > 0 and takes a share of the balance weight it cannot use, so the weights of the sources that
// can produce the point sum to less than 1 (too dark where visibility changes within the reuse
// radius; -0.6% of cornell's mean at 64×64). With the weights' targets as the reservoirs' (the
// honest restir target=visible) the shares sum to 1. Its analytic twin is ctl-reuse-unshadowed
// (estimators/negative_controls.cpp), on `blocker`.
// Parameters: M, N, radius (restir's). Declared workload: cornell at 64×64, 8 spp × 16
// replicates, against pt.
#include "estimators/scene/restir.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {

EstimatorEntry ctl_scene_reuse_unshadowed_entry() {
  EstimatorEntry e = scene_only_entry(
      "ctl-scene-reuse-unshadowed",
      "scenes: restir with visible targets whose balance weights see the sources' targets "
      "without visibility",
      {.params = reuse_control_params(),
       .make =
           [](const ResolvedParams& p) {
             scene::SceneRestirConfig config = reuse_control_config(p);
             config.weighting = {.form = ReuseWeights::kBalance};
             config.weights_without_visibility = true;
             return scene::make_scene_restir(config);
           }},
      true);
  e.declared = reuse_control_workload();
  return e;
}

}  // namespace pcbench

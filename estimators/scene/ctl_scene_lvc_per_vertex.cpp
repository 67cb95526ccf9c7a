// ctl-scene-lvc-per-vertex (scene negative control): the light vertex cache normalised by
// vertices instead of by paths.
//
// The mistake: each of the K uniform draws from the pool's N_v vertices is weighted 1 / K
// instead of N_v / (K M), so the connections sum to M / N_v times what they should (one over
// the mean number of vertices per path, < 1 wherever light bounces): biased low on every scene
// with more than direct light. Everything else is lvc's (lvc.cpp), with its parameters and
// defaults: M (1024), K (8). Declared workload: cornell, 16 spp × 16 replicates.
#include "estimators/scene/lvc.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {

EstimatorEntry ctl_scene_lvc_per_vertex_entry() {
  EstimatorEntry e = scene_only_entry(
      "ctl-scene-lvc-per-vertex",
      "scenes: the light vertex cache normalised by vertices instead of paths",
      {.params = scene::lvc_params(),
       .make =
           [](const ResolvedParams& p) {
             return scene::make_lvc(scene::read_lvc_config(p, {.per_vertex_normalisation = true}));
           }},
      true);
  e.declared = DeclaredWorkload{
      .integrand = "cornell", .samples = 16, .replicates = 16, .partners = {"plain"}};
  return e;
}

}  // namespace pcbench

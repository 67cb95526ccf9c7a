// ctl-scene-naive-reuse (scene negative control): restir (restir.cpp) with visible targets and
// the naive reuse weights m_s = 1/(k+1) (Bitterli et al. 2020's biased 1/ΣM), blended with the
// honest 1/Z by severity.
//
// The mistake: with visibility in the targets, a pixel in shadow holds a reservoir that cannot
// produce a point on the light its lit neighbour sees; 1/(k+1) still gives that source its share
// of the point's weight, so the weights of the sources that can produce it sum to less than 1 and
// lit pixels within the reuse radius of a shadow lose light (too dark along shadow edges; -6% of
// cornell's mean at 64×64). Severity 0 is restir with weights=count and target=visible, bit for
// bit. Its analytic twin is ctl-naive-reuse (estimators/negative_controls.cpp), on `blocker`.
// Parameters: M, N, radius (restir's), severity (share of the naive weights, default 1).
// Declared workload: cornell at 64×64, 8 spp × 16 replicates, against pt.
#include "estimators/scene/restir.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {

EstimatorEntry ctl_scene_naive_reuse_entry() {
  std::vector<ParamSpec> params = reuse_control_params();
  params.push_back({.name = "severity",
                    .type = ParamType::kReal,
                    .default_value = "1",
                    .description = "share of the naive weights 1/(k+1) (the rest 1/Z)",
                    .min = 0,
                    .max = 1});
  EstimatorEntry e = scene_only_entry(
      "ctl-scene-naive-reuse",
      "scenes: restir with visible targets and the naive reuse weights 1/(k+1) (biased 1/ΣM)",
      {.params = std::move(params),
       .make =
           [](const ResolvedParams& p) {
             scene::SceneRestirConfig config = reuse_control_config(p);
             config.weighting = {.form = ReuseWeights::kUniform, .naive_share = p.real("severity")};
             return scene::make_scene_restir(config);
           }},
      true);
  e.declared = reuse_control_workload();
  return e;
}

}  // namespace pcbench

// ctl-scene-nee-count (scene negative control): path tracing whose next-event estimates are
// divided by a sample count off by a fraction, a small bias over the whole image.
//
// The mistake: pt (pt.cpp) takes one emitter sample per camera vertex and its MIS weights count
// one, but each next-event estimate (strategy (1, t)) is divided by 1 + severity, as if it had
// taken 1 + severity samples; emitter hits (s = 0) are right. Each pixel is then low by
//     δ / (1 + δ) × (the share of its value that next-event estimation carries),   δ = severity,
// so the image is low by that factor times next-event estimation's share of the image. On
// cornell (at 32×32, max_length 5) that share is 98.7% (`pcbench run -e pt -i cornell
// --strategy-images`: the light is out of view and emitter hits carry 1.3%), so the bias is
// −1.94% at the default δ = 0.02, nearly uniform over the lit image: below what one 8×8 tile
// can detect at a CI budget, plain to a test on the whole image. On the furnace (every wall
// emits, so emitter hits carry the most) next-event estimation's share is 16.7%: −0.33%.
// severity = 0 is pt, bit for bit.
// Parameters: severity, δ in [0, 1] (default 0.02). Declared workload: cornell, 16 spp × 16
// replicates at its 32×32 default, against plain.
#include "estimators/scene/pt.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {

EstimatorEntry ctl_scene_nee_count_entry() {
  EstimatorEntry e = scene_only_entry(
      "ctl-scene-nee-count",
      "scenes: path tracing whose next-event estimates are divided by 1 + severity samples",
      {.params = {{.name = "severity",
                   .type = ParamType::kReal,
                   .default_value = "0.02",
                   .description = "δ: the next-event sample count taken as 1 + δ instead of 1",
                   .min = 0,
                   .max = 1}},
       .make =
           [](const ResolvedParams& p) {
             return scene::make_pt({.next_event_count = 1.0 + p.real("severity")});
           }},
      true);
  e.declared = DeclaredWorkload{
      .integrand = "cornell", .samples = 16, .replicates = 16, .partners = {"plain"}};
  return e;
}

}  // namespace pcbench

// ctl-scene-nee-count (scene negative control): path tracing whose next-event estimates are
// divided by a sample count off by a fraction: a small bias over the whole image, which the 8×8
// tiles miss at its CI-size workload and the block pyramid's whole-image scale catches.
//
// The mistake: pt (pt.cpp) takes one emitter sample per camera vertex and its MIS weights count
// one, but each next-event estimate (strategy (1, t)) is divided by 1 + δ, δ = severity, as if
// it had taken 1 + δ samples; emitter hits (s = 0) are right. Every path keeps its weights, so
// each pixel is low by exactly
//     δ / (1 + δ) × c_j,   c_j = the share of pixel j's value that next-event estimation carries,
// and the image by δ / (1 + δ) × c, c the share of the image. On cornell the light is out of view
// and emitter hits carry little: c = 98.7% (`pcbench run -e pt -i cornell -p resolution=128 -n 64
// -r 4 --strategy-images`: `image.strategies`, the s = 1 layers), c_j 96–100% over the lit pixels
// (97.6–99.3% per 8×8 tile), so at the default δ = 0.015 the bias is −1.46% and nearly uniform.
// On the furnace, whose walls all emit, emitter hits carry most of it: c = 16.7%, −0.25%.
// Why the tiles miss it: at 1 spp × 16 replicates an 8×8 tile's mean has a relative standard
// error of about 1.5% per estimator, so the bias moves each tile's Welch t by about 0.7, and the
// whole 128×128 image's (256 tiles) by about 16 × 0.7. At the declared workload (seeds 1–5,
// tests/global_bias_check.py) the pyramid's detectable bias is 46–74% at 8 px and 0.67–0.89% for
// the whole image: no 8×8 tile differs, the whole image does (adjusted p 1e-13 to 6e-10). At
// 16 spp the tiles see it too.
// Parameters: severity, δ in [0, 1] (default 0.015); 0 is pt bit for bit. Declared workload:
// cornell at 128×128, 1 spp × 16 replicates, against plain.
#include "estimators/scene/pt.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {

EstimatorEntry ctl_scene_nee_count_entry() {
  EstimatorEntry e = scene_only_entry(
      "ctl-scene-nee-count",
      "scenes: path tracing whose next-event estimates are divided by 1 + severity samples",
      {.params = {{.name = "severity",
                   .type = ParamType::kReal,
                   .default_value = "0.015",
                   .description = "δ: the next-event sample count taken as 1 + δ instead of 1",
                   .min = 0,
                   .max = 1}},
       .make =
           [](const ResolvedParams& p) {
             return scene::make_pt({.next_event_count = 1.0 + p.real("severity")});
           }},
      true);
  e.declared = DeclaredWorkload{.integrand = "cornell",
                                .integrand_params = {{"resolution", "128"}},
                                .samples = 1,
                                .replicates = 16,
                                .partners = {"plain"}};
  return e;
}

}  // namespace pcbench

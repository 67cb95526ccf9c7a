// The estimator family on scenes (integrands/scenes/scene_render.h): plain = BDPT, vc-all,
// lvc and pcbpt take scene parameters and render configurations beside their analytic ones;
// path tracing (`pt`) and light tracing (`lt`) exist on scenes only, as do the scene negative
// controls. Scene defaults follow public practice: M in the hundreds to W·H, K 3–16.
#pragma once

#include <vector>

#include "estimators/registry.h"

namespace pcbench {

// Gives the family's entries in `table` their scene form.
void add_scene_forms(std::vector<EstimatorEntry>& table);

// The estimators that work on scenes only: pt, lt and the scene negative controls.
std::vector<EstimatorEntry> scene_only_estimators();

}  // namespace pcbench

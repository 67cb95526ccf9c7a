// What a scene estimator's file includes to write its row: the scene estimators, one file each
// in this folder named after its registry key, each define the function that returns their
// whole row (`EstimatorEntry NAME_entry()`, listed in estimators/registry.cpp). The members of
// the family, which run on analytic integrands too, build it with family_entry
// (estimators/family_params.h); the others (path tracing, light tracing, the scene negative
// controls) with scene_only_entry. Scene defaults follow public practice: M in the hundreds to
// W·H, K 3–16.
#pragma once

#include <string>

#include "estimators/registry.h"
#include "estimators/scene/scene_form.h"

namespace pcbench {

// A row of the scene-only table: an estimator with a scene form and no analytic one.
EstimatorEntry scene_only_entry(std::string name, std::string description, SceneForm form,
                                bool biased = false);

}  // namespace pcbench

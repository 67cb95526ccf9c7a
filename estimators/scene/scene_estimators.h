// The scene estimators, one file each in this folder, named after its registry key. The members
// of the family that run on analytic integrands too give their scene form to their row in
// estimators/registry.cpp; the others (path tracing, light tracing, the scene negative controls)
// are whole rows of the scene-only table there. Scene defaults follow public practice: M in the
// hundreds to W·H, K 3–16.
#pragma once

#include <string>

#include "estimators/registry.h"
#include "estimators/scene/scene_form.h"

namespace pcbench {

SceneForm plain_scene_form();   // plain.cpp: BDPT
SceneForm vc_all_scene_form();  // vc_all.cpp: vertex connection to every light path
SceneForm lvc_scene_form();     // lvc.cpp: the light vertex cache
SceneForm pcbpt_scene_form();   // pcbpt.cpp: probabilistic connections

// A row of the scene-only table: an estimator with a scene form and no analytic one.
EstimatorEntry scene_only_entry(std::string name, std::string description, SceneForm form,
                                bool biased = false);

EstimatorEntry pt_entry();                        // pt.cpp: path tracing
EstimatorEntry lt_entry();                        // lt.cpp: light tracing
EstimatorEntry ctl_scene_visible_only_entry();    // ctl_scene_visible_only.cpp
EstimatorEntry ctl_scene_lvc_per_vertex_entry();  // ctl_scene_lvc_per_vertex.cpp
EstimatorEntry ctl_scene_nee_count_entry();       // ctl_scene_nee_count.cpp

}  // namespace pcbench

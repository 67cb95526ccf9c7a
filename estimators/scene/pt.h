// Path tracing (pt.cpp), configurable for its negative control (ctl_scene_nee_count.cpp).
#pragma once

#include <memory>

#include "estimators/scene/scene_estimator.h"

namespace pcbench::scene {

struct PtConfig {
  // The control's mistake: each next-event estimate is divided by this sample count, while the
  // pass takes one emitter sample per camera vertex and the MIS weights count one. 1 is honest.
  double next_event_count = 1.0;
};

std::shared_ptr<const SceneEstimator> make_pt(const PtConfig& config);

}  // namespace pcbench::scene

// ris on scenes: path tracing whose next-event estimation resamples M emitter points at every
// camera vertex (emitter_resampling.h). Its row is estimators/ris.cpp (the analytic form beside
// it); restir (restir.h) builds on the same step.
#pragma once

#include <cstdint>
#include <memory>

#include "estimators/scene/emitter_resampling.h"
#include "estimators/scene/scene_form.h"

namespace pcbench::scene {

struct SceneRisConfig {
  std::uint32_t candidates = 16;  // M emitter points per camera vertex
  EmitterTarget target = EmitterTarget::kUnshadowed;
};

// The counts of path tracing (pt.cpp): one emitter hit and one next event per camera vertex.
// RIS's density of Y has no closed form, so the balance heuristic weighs the next event as one
// sample of the emitters' own density q; any such choice sums to 1 with the emitter hit's weight,
// and RIS estimates whatever share w_{1,t} f it is given (its target is > 0 wherever that is).
StrategyCounts next_event_counts();

std::shared_ptr<const SceneEstimator> make_scene_ris(const SceneRisConfig& config);

}  // namespace pcbench::scene

namespace pcbench {

// M: emitter candidates per camera vertex; target: unshadowed or visible.
ParamSpec emitter_candidates_spec(std::uint32_t default_value);
ParamSpec emitter_target_spec();
// The parameters above in `config`.
void read_scene_ris_params(const ResolvedParams& params, scene::SceneRisConfig& config);

SceneForm ris_scene_form();

}  // namespace pcbench

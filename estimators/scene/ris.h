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

// The MIS counts: one emitter hit per camera vertex, and the next event counted as `candidates`
// samples of the emitters' own density q, as if every candidate were kept. RIS's density of Y
// has no closed form, so the balance heuristic needs a stand-in; any counts sum to 1 with the
// emitter hit's weight, and RIS estimates whatever share w_{1,t} f it is given (its target is
// > 0 wherever that is). Counting the M candidates gives a light the next event reaches with M
// tries the weight M tries earn, not one: with one, a dim light that BSDF sampling hits keeps
// most of its weight in the noisy emitter hit. With M = 1 these are pt's counts.
StrategyCounts next_event_counts(std::uint32_t candidates);

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

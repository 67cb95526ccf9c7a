// ris (scenes): path tracing with resampled next-event estimation (Talbot et al. 2005).
//
// As pt (pt.cpp), every camera prefix y_0 .. y_{t-1} (t >= 2) adds its own emitter hit,
// strategy (0, t), and one next event, strategy (1, t); the next event's emitter point Y is the
// one a reservoir keeps of M candidates X_i ~ q (emitter_resampling.h), weighted by RIS's
// contribution weight:
//     <I_j> = Σ_t [ w_{0,t} f / p_{0,t} + f_w(Y) W ],   W = (1/M) Σ_i p̂(X_i)/q(X_i) / p̂(Y),
// with f_w = w_{1,t} f the MIS-weighted next event and p̂ the largest channel of f without the
// weight, unshadowed or with visibility (target). The MIS counts are n_{0,t} = 1 and n_{1,t} = M
// with p_{1,t} = q (next_event_counts, ris.h): the weights sum to 1 for any counts, and RIS
// estimates the share w_{1,t} f unbiasedly because p̂ > 0 wherever f_w > 0. With M = 1 it is pt up
// to rounding (the same streams and counts).
// Parameters: M (candidates, default 16), target (unshadowed, or visible: a shadow ray each).
#include "estimators/scene/ris.h"

#include <string>

namespace pcbench::scene {
namespace {

class RisPass final : public ScenePass {
 public:
  RisPass(const RenderServices& services, const SceneRisConfig& config)
      : services_(services), config_(config) {}

  // The unshadowed target's kept point is queued, its connection made with the row's others in
  // lanes; the visible target has traced its shadow ray already, and shades at once.
  bool queues_connections() const override { return config_.target == EmitterTarget::kUnshadowed; }
  void queue_connections(const LightPool&, CameraPrefix& prefix,
                         ConnectionQueue& queue) const override {
    queue_emitter_sample(resample_emitters(services_, prefix, config_.candidates, config_.target),
                         prefix, queue);
  }

  Rgb connections(const LightPool&, CameraPrefix& prefix) const override {
    const EmitterSample y =
        resample_emitters(services_, prefix, config_.candidates, config_.target);
    const Rgb value = shade_emitter_sample(services_, y.point, y.at_owner, y.contribution_weight,
                                           prefix.vertices, config_.target, prefix.counters);
    services_.record(1, prefix, value);
    return value;
  }

 private:
  const RenderServices& services_;
  SceneRisConfig config_;
};

class Ris final : public SceneEstimator {
 public:
  explicit Ris(const SceneRisConfig& config) : config_(config) {}

  std::uint32_t pool_size(const Scene&) const override { return 0; }
  StrategyCounts strategy_counts(const Scene&) const override {
    return next_event_counts(config_.candidates);
  }
  bool samples_all_paths(const Scene& scene) const override { return !needs_light_subpaths(scene); }
  std::unique_ptr<ScenePass> begin_replicate(const RenderServices& services) const override {
    return std::make_unique<RisPass>(services, config_);
  }

 private:
  SceneRisConfig config_;
};

}  // namespace

StrategyCounts next_event_counts(std::uint32_t candidates) {
  return {.emitter_hit = 1.0,
          .next_event = static_cast<double>(candidates),
          .connection = 0.0,
          .light_tracing = 0.0};
}

std::shared_ptr<const SceneEstimator> make_scene_ris(const SceneRisConfig& config) {
  return std::make_shared<Ris>(config);
}

}  // namespace pcbench::scene

namespace pcbench {

ParamSpec emitter_candidates_spec(std::uint32_t default_value) {
  return {.name = "M",
          .type = ParamType::kInt,
          .default_value = std::to_string(default_value),
          .description = "emitter candidates per camera vertex, streamed through a reservoir",
          .min = 1,
          .max = 1024};
}

ParamSpec emitter_target_spec() {
  return {.name = "target",
          .type = ParamType::kChoice,
          .default_value = "unshadowed",
          .description =
              "target p̂: the next event's MIS-weighted contribution without its "
              "shadow ray, or with it (a shadow ray per candidate)",
          .choices = {"unshadowed", "visible"}};
}

void read_scene_ris_params(const ResolvedParams& params, scene::SceneRisConfig& config) {
  if (params.has("M")) config.candidates = static_cast<std::uint32_t>(params.integer("M"));
  if (params.has("target")) {
    config.target = params.text("target") == "visible" ? scene::EmitterTarget::kVisible
                                                       : scene::EmitterTarget::kUnshadowed;
  }
}

SceneForm ris_scene_form() {
  return {.params = {emitter_candidates_spec(16), emitter_target_spec()},
          .make = [](const ResolvedParams& params) {
            scene::SceneRisConfig config;
            read_scene_ris_params(params, config);
            return scene::make_scene_ris(config);
          }};
}

}  // namespace pcbench

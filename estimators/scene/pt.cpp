// pt (scenes only): path tracing with next-event estimation.
//
// Estimates the image I_j = ∫ f_j(z) dz over paths z of 1 .. max_length edges with one camera
// subpath y_0 .. y_{n} per pixel and iteration and no pool: every camera prefix y_0 .. y_{t-1}
// (t >= 2) adds its own emitter hit, strategy (0, t), and connects to one emitter vertex x_0
// sampled by power and area (strategy (1, t), next-event estimation), each weighted by the
// balance heuristic over the two (Veach's thesis, ch. 9–10):
//     <I_j> = Σ_t [ w_{0,t} f / p_{0,t} + w_{1,t} f / p_{1,t} ],   counts n_{0,t} = n_{1,t} = 1.
// Parameters: none. Misses point light → mirror paths (no emitter to hit, no diffuse vertex to
// connect at), so it is no reference on scenes that have both.
#include "estimators/scene/pt.h"

#include "estimators/scene/scene_estimators.h"

namespace pcbench {
namespace scene {
namespace {

class PathTracingPass final : public ScenePass {
 public:
  PathTracingPass(const RenderServices& services, const PtConfig& config)
      : services_(services), config_(config) {}

  // pt itself queues its one next-event connection per prefix; the control, which scales it,
  // connects at once.
  bool queues_connections() const override { return config_.next_event_count == 1.0; }
  void queue_connections(const LightPool&, CameraPrefix& prefix,
                         ConnectionQueue& queue) const override {
    // From the camera stream, where the pixel's subpath left it; the point is made with the
    // row's others, in lanes.
    queue.connect_emitter_sample(prefix.camera, prefix);
  }

  Rgb connections(const LightPool&, CameraPrefix& prefix) const override {
    // The control's mistake (ctl_scene_nee_count.cpp): one sample divided by another count.
    const PathVertex emitter = sample_emitter_vertex(services_.scene(), prefix.camera);
    const Rgb value = services_.connect(std::span(&emitter, 1), prefix) / config_.next_event_count;
    services_.record(1, prefix, value);
    return value;
  }

 private:
  const RenderServices& services_;
  PtConfig config_;
};

class PathTracing final : public SceneEstimator {
 public:
  explicit PathTracing(const PtConfig& config) : config_(config) {}

  std::uint32_t pool_size(const Scene&) const override { return 0; }
  StrategyCounts strategy_counts(const Scene&) const override {
    return {.emitter_hit = 1.0, .next_event = 1.0, .connection = 0.0, .light_tracing = 0.0};
  }
  bool samples_all_paths(const Scene& scene) const override { return !needs_light_subpaths(scene); }
  std::unique_ptr<ScenePass> begin_replicate(const RenderServices& services) const override {
    return std::make_unique<PathTracingPass>(services, config_);
  }

 private:
  PtConfig config_;
};

}  // namespace

std::shared_ptr<const SceneEstimator> make_pt(const PtConfig& config) {
  return std::make_shared<PathTracing>(config);
}

}  // namespace scene

EstimatorEntry pt_entry() {
  return scene_only_entry(
      "pt", "scenes: path tracing with next-event estimation (s <= 1)",
      {.params = {}, .make = [](const ResolvedParams&) { return scene::make_pt({}); }});
}

}  // namespace pcbench

// example-nee (scenes only; the worked example of docs/dev/extending.md "Adding a scene estimator",
// registered in the pcbench_examples binary only): path tracing with N next-event samples per
// camera vertex.
//
// Estimates the image with one camera subpath per pixel and iteration and no pool: every camera
// prefix y_0 .. y_{t-1} (t >= 2) adds its own emitter hit (strategy (0, t), 1 sample) and
// connects to N emitter vertices sampled by power and area (strategy (1, t), N samples), each
// weighted 1/N and by the balance heuristic over those counts (Veach's thesis, sec. 9.2.4,
// multi-sample MIS):
//     <I_j> = Σ_t [ w_0 f / p_0 + 1/N Σ_{n<N} w_1 f / p_1 ],   w_1 = N p_1 / (p_0 + N p_1).
// N = 1 is `pt`. Parameters: emitter_samples N (default 2).
//
// All of it is this file, which ends with its row (example_nee_entry, the estimator whole), one
// line of the examples' registry (examples/examples.cpp) and one of the build (CMakeLists.txt,
// pcbench_example_estimators): tests/scene_mis_test.cpp reads it from there, with no edit.
#include "estimators/scene/scene_estimators.h"

namespace pcbench::examples {
namespace {

constexpr std::uint32_t kDefaultEmitterSamples = 2;

// What one replicate keeps: nothing but the renderer's services (no per-iteration state).
class NeePass final : public scene::ScenePass {
 public:
  NeePass(const scene::RenderServices& services, std::uint32_t emitter_samples)
      : services_(services), emitter_samples_(emitter_samples) {}

  // Queued: the renderer traces the shadow rays of a whole row of pixels in packets, then adds
  // each connection (share × its MIS-weighted value) to the pixel and to its strategy image.
  bool queues_connections() const override { return true; }
  void queue_connections(const scene::LightPool&, scene::CameraPrefix& prefix,
                         scene::ConnectionQueue& queue) const override {
    const double share = 1.0 / emitter_samples_;
    for (std::uint32_t n = 0; n < emitter_samples_; ++n) {
      queue.connect(scene::sample_emitter_vertex(services_.scene(), prefix.draws), prefix, share);
    }
  }

 private:
  const scene::RenderServices& services_;
  std::uint32_t emitter_samples_;
};

class NextEventEstimation final : public scene::SceneEstimator {
 public:
  explicit NextEventEstimation(std::uint32_t emitter_samples) : emitter_samples_(emitter_samples) {}

  std::uint32_t pool_size(const scene::Scene&) const override { return 0; }  // no light paths
  scene::StrategyCounts strategy_counts(const scene::Scene&) const override {
    return {.emitter_hit = 1.0,
            .next_event = static_cast<double>(emitter_samples_),
            .connection = 0.0,
            .light_tracing = 0.0};
  }
  bool samples_all_paths(const scene::Scene& scene) const override {
    return !scene::needs_light_subpaths(scene);
  }
  std::unique_ptr<scene::ScenePass> begin_replicate(
      const scene::RenderServices& services) const override {
    return std::make_unique<NeePass>(services, emitter_samples_);
  }

 private:
  std::uint32_t emitter_samples_;
};

}  // namespace

EstimatorEntry example_nee_entry() {
  const ParamSpec emitter_samples{.name = "emitter_samples",
                                  .type = ParamType::kInt,
                                  .default_value = std::to_string(kDefaultEmitterSamples),
                                  .description = "emitter vertices sampled per camera vertex",
                                  .min = 1,
                                  .max = 64};
  return scene_only_entry(
      "example-nee", "scenes (example): path tracing with N next-event samples per vertex",
      {.params = {emitter_samples}, .make = [](const ResolvedParams& p) {
         return std::shared_ptr<const scene::SceneEstimator>(std::make_shared<NextEventEstimation>(
             static_cast<std::uint32_t>(p.integer("emitter_samples"))));
       }});
}

}  // namespace pcbench::examples

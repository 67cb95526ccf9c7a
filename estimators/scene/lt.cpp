// lt (scenes only): light tracing.
//
// Estimates the image with W·H light subpaths x_0 .. x_{n} per iteration and no camera
// subpaths: every light prefix x_0 .. x_{s-1} connects to the camera (strategy (s, 1)) and lands
// in the pixel it projects to, weighted 1 / (W·H) and by the balance heuristic over light
// tracing alone (count W·H; Veach's thesis, ch. 10):
//     <I_j> = 1/M Σ_{paths} Σ_s w_{s,1} f_j / p_{s,1},   M = W·H.
// Parameters: none. Misses camera → mirror paths (nothing connects through a mirror to the lens),
// so it is no reference on scenes with specular surfaces.
#include "estimators/scene/scene_estimators.h"

namespace pcbench {
namespace {

// Light tracing traces no camera subpaths (strategy_counts below), so it has no connections.
class LightTracingPass final : public scene::ScenePass {
 public:
  scene::Rgb connections(const scene::LightPool&, scene::CameraPrefix&) const override {
    return {};
  }
};

class LightTracing final : public scene::SceneEstimator {
 public:
  std::uint32_t pool_size(const scene::Scene& scene) const override {
    return scene.description().width * scene.description().height;
  }
  scene::StrategyCounts strategy_counts(const scene::Scene& scene) const override {
    const double pool = pool_size(scene);
    return {.emitter_hit = 0.0, .next_event = 0.0, .connection = 0.0, .light_tracing = pool};
  }
  bool samples_all_paths(const scene::Scene& scene) const override {
    return !scene.traits().has_specular;
  }
  std::unique_ptr<scene::ScenePass> begin_replicate(const scene::RenderServices&) const override {
    return std::make_unique<LightTracingPass>();
  }
};

}  // namespace

EstimatorEntry lt_entry() {
  return scene_only_entry(
      "lt", "scenes: light tracing, W·H light paths splatted (t = 1)",
      {.params = {}, .make = [](const ResolvedParams&) {
         return std::shared_ptr<const scene::SceneEstimator>(std::make_shared<LightTracing>());
       }});
}

}  // namespace pcbench

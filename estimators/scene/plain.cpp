// plain on scenes: bidirectional path tracing (BDPT); also named bdpt (the same runs and ids).
//
// Estimates the image with W·H light subpaths per iteration and one camera subpath per pixel;
// pixel i connects to light subpath i only (one fresh light path per camera sample, as plain
// does on analytic integrands: M = K = 1). Every strategy (s, t) of a path is sampled once per
// pixel and iteration, light tracing (t = 1) W·H times, all weighted by the balance heuristic
// (Veach's thesis, ch. 10; Veach and Guibas 1995):
//     <I_j> = Σ_{s,t} w_{s,t} f / p_{s,t},   counts n_{0,t} = n_{s>=1,t>=2} = 1, n_{s,1} = W·H.
// Parameters on scenes: none.
#include "estimators/family_params.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {
namespace {

class BdptPass final : public scene::ScenePass {
 public:
  bool queues_connections() const override { return true; }
  void queue_connections(const scene::LightPool& pool, scene::CameraPrefix& prefix,
                         scene::ConnectionQueue& queue) const override {
    const scene::Subpath& path = pool.paths[prefix.pixel];
    for (std::uint32_t s = 1; s <= std::min<std::uint32_t>(prefix.max_s, path.size()); ++s) {
      queue.connect(std::span(path).first(s), prefix);
    }
  }
};

class Bdpt final : public scene::SceneEstimator {
 public:
  std::uint32_t pool_size(const scene::Scene& scene) const override {
    return scene.description().width * scene.description().height;
  }
  scene::StrategyCounts strategy_counts(const scene::Scene& scene) const override {
    const double pool = pool_size(scene);
    return {.emitter_hit = 1.0, .next_event = 1.0, .connection = 1.0, .light_tracing = pool};
  }
  std::unique_ptr<scene::ScenePass> begin_replicate(const scene::RenderServices&) const override {
    return std::make_unique<BdptPass>();
  }
};

}  // namespace

EstimatorEntry plain_entry() {
  EstimatorEntry entry =
      family_entry("plain", "one fresh light path per camera sample, connected once (M = K = 1)",
                   {}, Selection::kAll, DrawScheme::kEvery,
                   {.params = {}, .make = [](const ResolvedParams&) {
                      return std::shared_ptr<const scene::SceneEstimator>(std::make_shared<Bdpt>());
                    }});
  entry.aliases = {"bdpt"};  // what it is on scenes
  return entry;
}

}  // namespace pcbench

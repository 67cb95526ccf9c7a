// vc-all on scenes: vertex connection to every light path of a pool.
//
// Estimates the image with M light subpaths per iteration shared by every pixel: every camera
// vertex y_{t-1} (t >= 2) connects to every vertex of every pool path, weighted 1/M, so each
// connection strategy (s >= 1, t >= 2) is sampled M times per pixel and iteration; the camera
// subpath's emitter hits (s = 0) once, light tracing (t = 1) M times; balance heuristic over
// those counts:
//     <I_j> = Σ_t [ w_{0,t} f / p_{0,t} + 1/M Σ_{paths} Σ_s w_{s,t} f / p_{s,t} ] + light tracing.
// Parameters on scenes: M, light paths per iteration (default 8).
#include "estimators/family_params.h"
#include "estimators/scene/scene_estimators.h"

namespace pcbench {
namespace {

constexpr std::uint32_t kDefaultLightPaths = 8;

class VertexConnectionPass final : public scene::ScenePass {
 public:
  // Every vertex of every pool path, each connection times 1/M, queued: the row's shadow rays
  // go to Embree as packets and their values and weights to SIMD lanes (connection_queue.h).
  bool queues_connections() const override { return true; }
  void queue_connections(const scene::LightPool& pool, scene::CameraPrefix& prefix,
                         scene::ConnectionQueue& queue) const override {
    const double per_path = 1.0 / static_cast<double>(pool.paths.size());
    for (const scene::Subpath& path : pool.paths) {
      for (std::uint32_t s = 1; s <= std::min<std::uint32_t>(prefix.max_s, path.size()); ++s) {
        queue.connect(std::span(path).first(s), prefix, per_path);
      }
    }
  }
};

class VertexConnection final : public scene::SceneEstimator {
 public:
  explicit VertexConnection(std::uint32_t light_paths) : light_paths_(light_paths) {}

  std::uint32_t pool_size(const scene::Scene&) const override { return light_paths_; }
  scene::StrategyCounts strategy_counts(const scene::Scene& scene) const override {
    const double pool = pool_size(scene);
    return {.emitter_hit = 1.0, .next_event = pool, .connection = pool, .light_tracing = pool};
  }
  std::unique_ptr<scene::ScenePass> begin_replicate(const scene::RenderServices&) const override {
    return std::make_unique<VertexConnectionPass>();
  }

 private:
  std::uint32_t light_paths_;
};

}  // namespace

EstimatorEntry vc_all_entry() {
  return family_entry(
      "vc-all", "vertex connection to every light path of a pool of M",
      {pool_size_spec(), pool_mode_spec()}, Selection::kAll, DrawScheme::kEvery,
      {.params = {light_paths_spec(kDefaultLightPaths)}, .make = [](const ResolvedParams& p) {
         return std::shared_ptr<const scene::SceneEstimator>(
             std::make_shared<VertexConnection>(static_cast<std::uint32_t>(p.integer("M"))));
       }});
}

}  // namespace pcbench

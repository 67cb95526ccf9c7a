// lvc on scenes: the light vertex cache (Davidovič et al., "Progressive light transport
// simulation on the GPU", ACM TOG 33(3), 2014).
//
// Estimates the image with M light subpaths per iteration shared by every pixel: the pool's N_v
// vertices form the cache, and every camera vertex y_{t-1} (t >= 2) connects to K of them drawn
// uniformly with replacement, each weighted N_v / (K M) (vertices drawn, paths counted: a
// vertex is drawn K / N_v times in expectation and each path holds N_v / M of them on average,
// so the estimate is the one of connecting to every vertex divided by M). Connection strategies
// (s >= 1, t >= 2) count K samples per pixel and iteration, emitter hits 1, light tracing M:
//     <I_j> = Σ_t [ w_{0,t} f / p_{0,t} + Σ_{k<K} N_v/(K M) w_{s_k,t} f / p_{s_k,t} ] + light
//     tracing.
// Parameters on scenes: M, light paths per iteration (default 1024); K, draws per camera vertex
// (default 8).
#include "estimators/scene/lvc.h"

#include "estimators/family_params.h"
#include "estimators/scene/scene_estimators.h"
#include "estimators/scene/vertex_draws.h"

namespace pcbench {
namespace scene {
namespace {

class LightVertexCachePass final : public ScenePass {
 public:
  explicit LightVertexCachePass(const LvcConfig& config) : config_(config) {}

  void prepare(const LightPool& pool, TraceCounters&) override { vertices_ = light_vertices(pool); }

  bool queues_connections() const override { return true; }
  void queue_connections(const LightPool& pool, CameraPrefix& prefix,
                         ConnectionQueue& queue) const override {
    if (vertices_.empty()) return;
    UniformVertexDraw draw =
        uniform_vertex_draw(vertices_.size(), pool.paths.size(), config_.draws);
    if (config_.per_vertex_normalisation)
      draw.coefficient = 1.0 / static_cast<double>(config_.draws);
    queue_drawn_vertices(pool, vertices_, prefix, config_.draws, draw, queue);
  }

 private:
  LvcConfig config_;
  std::vector<LightVertexRef> vertices_;
};

class LightVertexCache final : public SceneEstimator {
 public:
  explicit LightVertexCache(const LvcConfig& config) : config_(config) {}

  std::uint32_t pool_size(const Scene&) const override { return config_.light_paths; }
  StrategyCounts strategy_counts(const Scene&) const override {
    return vertex_draw_counts(config_.light_paths, config_.draws);
  }
  std::unique_ptr<ScenePass> begin_replicate(const RenderServices&) const override {
    return std::make_unique<LightVertexCachePass>(config_);
  }

 private:
  LvcConfig config_;
};

}  // namespace

std::vector<ParamSpec> lvc_params() {
  const LvcConfig defaults;
  return {light_paths_spec(defaults.light_paths), vertex_draws_spec(defaults.draws)};
}

LvcConfig read_lvc_config(const ResolvedParams& p, LvcConfig base) {
  base.light_paths = static_cast<std::uint32_t>(p.integer("M"));
  base.draws = static_cast<std::uint32_t>(p.integer("K"));
  return base;
}

std::shared_ptr<const SceneEstimator> make_lvc(const LvcConfig& config) {
  return std::make_shared<LightVertexCache>(config);
}

}  // namespace scene

EstimatorEntry lvc_entry() {
  EstimatorEntry entry = family_entry(
      "lvc", "light vertex cache: K uniform draws from the pool's M light vertices",
      {pool_size_spec(), draws_spec(), pool_mode_spec(), draw_scheme_spec()}, Selection::kUniform,
      DrawScheme::kIndependent,
      {.params = scene::lvc_params(),
       .make = [](const ResolvedParams& p) { return scene::make_lvc(scene::read_lvc_config(p)); }});
  // The furnace test's 8×8 image needs a smaller pool than a typical run.
  entry.scene_tests.renders = {{"M=256 K=4", {{"M", "256"}, {"K", "4"}}}};
  return entry;
}

}  // namespace pcbench

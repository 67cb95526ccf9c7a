// pcbpt on scenes: probabilistic connections (Popov et al., "Probabilistic Connections for
// Bidirectional Path Tracing", CGF 34(4), EGSR 2015).
//
// Estimates the image with M light subpaths per iteration shared by every pixel. Each screen
// tile of `tile` × `tile` pixels has a cache point, the first hit through its centre (fixed for
// the replicate, so the guidance depends on no pool). Per iteration and tile, P over the pool's
// N_v light vertices is proportional to the unoccluded connection value at the cache point
// (largest channel; with visibility=cache-point times the cache point's visibility), mixed with
// uniform: P_i = (1 - u) w_i / Σ w + u / N_v. The first vertex of every camera subpath (t = 2)
// draws K light vertices from its tile's P, each weighted 1 / (K M P_i); deeper camera vertices
// draw uniformly, weighted N_v / (K M), as the light vertex cache does (guide=all: every vertex
// from the tile's P). Connection strategies count K samples per pixel and iteration, emitter
// hits 1, light tracing M:
//     <I_j> = Σ_t [ w_{0,t} f / p_{0,t} + Σ_{k<K} 1/(K M P_{ξk}) w_{s_k,t} f / p_{s_k,t} ] + lt.
// Unbiased wherever P > 0 where f > 0: always with u > 0.
// Parameters on scenes (defaults in PcbptConfig, pcbpt.h): M (1024), K (8), uniform_mix u
// (0.1), tile (8), guide first|all (first), visibility ignored|cache-point (ignored; needs
// u > 0).
#include "estimators/scene/pcbpt.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "base/errors.h"
#include "estimators/discrete_sampler.h"
#include "estimators/resampling_step.h"
#include "estimators/scene/scene_estimators.h"
#include "estimators/scene/vertex_draws.h"

namespace pcbench {
namespace scene {
namespace {

class ProbabilisticPass final : public ScenePass {
 public:
  ProbabilisticPass(const RenderServices& services, const PcbptConfig& config)
      : services_(services),
        config_(config),
        tiles_x_((services.width() + config.tile - 1) / config.tile),
        tiles_y_((services.height() + config.tile - 1) / config.tile) {
    trace_cache_points();
  }

  void prepare(const LightPool& pool, TraceCounters& counters) override {
    vertices_ = light_vertices(pool);
    build_tile_distributions(pool, counters);
  }

  Rgb connections(const LightPool& pool, CameraPrefix& prefix) const override {
    if (vertices_.empty()) return {};
    // The tile's cache point stands for the first camera vertex only (unless guide_all): deeper
    // vertices lie elsewhere and draw uniformly, as the light vertex cache does.
    if (!config_.guide_all && prefix.t() > 2) {
      return connect_drawn_vertices(
          services_, pool, vertices_, prefix, config_.draws,
          uniform_vertex_draw(vertices_.size(), pool.paths.size(), config_.draws));
    }
    const std::uint32_t tile = tile_of(prefix.pixel);
    if (!tile_has_draws_[tile]) return {};
    const double k = config_.draws;
    const double m = static_cast<double>(pool.paths.size());
    const std::vector<double>& pmf = tile_pmf_[tile];
    const DiscreteSampler& sampler = tile_sampler_[tile];
    return connect_drawn_vertices(services_, pool, vertices_, prefix, config_.draws,
                                  [&](RandomStream& draws) {
                                    const std::uint32_t index = sampler.draw(draws);
                                    return VertexDraw{index, 1.0 / (k * m * pmf[index])};
                                  });
  }

 private:
  std::uint32_t tile_of(std::uint32_t pixel) const {
    const std::uint32_t x = pixel % services_.width(), y = pixel / services_.width();
    return (y / config_.tile) * tiles_x_ + x / config_.tile;
  }

  void trace_cache_points() {
    const double width = services_.width(), height = services_.height();
    TraceCounters ignored;
    cache_paths_.resize(std::size_t{tiles_x_} * tiles_y_);
    for (std::uint32_t ty = 0; ty < tiles_y_; ++ty) {
      for (std::uint32_t tx = 0; tx < tiles_x_; ++tx) {
        const double cx = std::min<double>(width, (tx + 0.5) * config_.tile);
        const double cy = std::min<double>(height, (ty + 0.5) * config_.tile);
        RandomStream unused(services_.stream(StreamPurpose::kEstimatorAux, 0, ty * tiles_x_ + tx));
        trace_camera_path(services_.scene(), std::min(cx, width - 0.5), std::min(cy, height - 0.5),
                          unused, 1, cache_paths_[ty * tiles_x_ + tx], ignored);
      }
    }
  }

  void build_tile_distributions(const LightPool& pool, TraceCounters& counters) {
    const std::size_t tiles = cache_paths_.size();
    const std::uint32_t n = static_cast<std::uint32_t>(vertices_.size());
    tile_pmf_.assign(tiles, {});
    tile_sampler_.assign(tiles, {});
    tile_has_draws_.assign(tiles, 0);
    if (n == 0) return;
    const ResamplingStep step(StepConfig{.M = n,
                                         .K = config_.draws,
                                         .selection = Selection::kImportance,
                                         .scheme = DrawScheme::kIndependent,
                                         .uniform_mix = config_.uniform_mix,
                                         .sampler = DiscreteSamplerKind::kAlias});
    std::vector<TraceCounters> tile_counters(tiles);
    tbb::parallel_for(std::size_t{0}, tiles, [&](std::size_t tile) {
      std::vector<double> importance(n, 0.0);
      const Subpath& cache = cache_paths_[tile];
      if (cache.size() == 2) {
        const ConnectOptions options{.visibility = config_.cache_visibility, .weighted = false};
        for (std::uint32_t i = 0; i < n; ++i) {
          importance[i] =
              services_
                  .connect(light_prefix(pool, vertices_[i]), cache, options, tile_counters[tile])
                  .max_channel();
        }
      }
      double total = 0.0;
      for (double w : importance) total += w;
      // With no mixing and nothing visible there is nothing to draw from (the control's bias).
      if (config_.unseen_tiles_draw_nothing && total == 0.0) return;
      step.build_pmf(PoolView{.importance = importance}, tile_pmf_[tile]);
      tile_sampler_[tile].build(tile_pmf_[tile], DiscreteSamplerKind::kAlias);
      tile_has_draws_[tile] = 1;
    });
    for (const TraceCounters& c : tile_counters) counters.add(c);
  }

  const RenderServices& services_;
  PcbptConfig config_;
  std::uint32_t tiles_x_, tiles_y_;
  std::vector<Subpath> cache_paths_;  // per tile: the camera vertex and its first hit
  // Per iteration: the pool's vertices and, per tile, P over them and its sampler.
  std::vector<LightVertexRef> vertices_;
  std::vector<std::vector<double>> tile_pmf_;
  std::vector<DiscreteSampler> tile_sampler_;
  // One byte per tile, not std::vector<bool>: tiles are built in parallel, and the bits of a
  // vector<bool> share words, so two tiles' writes would race and one could be lost.
  std::vector<std::uint8_t> tile_has_draws_;
};

class Probabilistic final : public SceneEstimator {
 public:
  explicit Probabilistic(const PcbptConfig& config) : config_(config) {}

  std::uint32_t pool_size(const Scene&) const override { return config_.light_paths; }
  StrategyCounts strategy_counts(const Scene&) const override {
    return vertex_draw_counts(config_.light_paths, config_.draws);
  }
  std::unique_ptr<ScenePass> begin_replicate(const RenderServices& services) const override {
    return std::make_unique<ProbabilisticPass>(services, config_);
  }

 private:
  PcbptConfig config_;
};

ParamSpec mix_spec(double default_value) {
  return {.name = "uniform_mix",
          .type = ParamType::kReal,
          .default_value = to_text(default_value),
          .description = "fraction of P spread uniformly over the light vertices",
          .min = 0.0,
          .max = 1.0};
}

ParamSpec guide_spec(bool all) {
  return {.name = "guide",
          .type = ParamType::kChoice,
          .default_value = all ? "all" : "first",
          .description =
              "camera vertices drawn from the tile's P: the first (deeper ones "
              "uniformly), or all",
          .choices = {"first", "all"}};
}

ParamSpec visibility_spec(bool cache_point) {
  return {.name = "visibility",
          .type = ParamType::kChoice,
          .default_value = cache_point ? "cache-point" : "ignored",
          .description =
              "importance at the cache point: the unoccluded connection value (ignored), or "
              "times its visibility (cache-point: one shadow ray per tile and light vertex; "
              "needs uniform_mix > 0)",
          .choices = {"ignored", "cache-point"}};
}

PcbptConfig read_config(const ResolvedParams& p) {
  PcbptConfig c;
  c.light_paths = static_cast<std::uint32_t>(p.integer("M"));
  c.draws = static_cast<std::uint32_t>(p.integer("K"));
  c.uniform_mix = p.real("uniform_mix");
  c.tile = static_cast<std::uint32_t>(p.integer("tile"));
  c.guide_all = p.text("guide") == "all";
  c.cache_visibility = p.text("visibility") == "cache-point";
  // Light the cache point cannot see may reach other pixels of its tile: only the uniform share
  // keeps P > 0 for it (without it this is the control ctl-scene-visible-only).
  if (c.cache_visibility && !(c.uniform_mix > 0.0)) {
    throw InputError(
        "visibility=cache-point needs uniform_mix > 0: without mixing, light vertices the cache "
        "point cannot see are never drawn for the pixels of its tile that can (biased; that is "
        "the negative control ctl-scene-visible-only)");
  }
  return c;
}

}  // namespace

std::shared_ptr<const SceneEstimator> make_pcbpt(const PcbptConfig& config) {
  return std::make_shared<Probabilistic>(config);
}

}  // namespace scene

SceneForm pcbpt_scene_form() {
  const scene::PcbptConfig d;
  return {.params = {light_paths_spec(d.light_paths), vertex_draws_spec(d.draws),
                     scene::mix_spec(d.uniform_mix), tile_spec(d.tile),
                     scene::guide_spec(d.guide_all), scene::visibility_spec(d.cache_visibility)},
          .make = [](const ResolvedParams& p) { return scene::make_pcbpt(scene::read_config(p)); }};
}

}  // namespace pcbench

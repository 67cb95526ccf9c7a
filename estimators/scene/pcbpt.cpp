// pcbpt on scenes: probabilistic connections (Popov, Ramamoorthi, Durand, Drettakis,
// "Probabilistic Connections for Bidirectional Path Tracing", CGF 34(4), EGSR 2015).
//
// Estimates the image with a pool of light subpaths per iteration shared by every pixel: its
// first M paths' N_v vertices x_i are the connections' candidates (under nee=fresh those with
// s >= 2 only), and light tracing (t = 1) splats every pool path: M of them (light_tracing=M), or
// max(M, W·H) as BDPT splats W·H (light_tracing=pixels).
// Cache points y_c are the non-specular vertices, at every camera depth, of cache paths traced
// once per replicate through the centres of `grid` × `grid` pixel blocks (fixed per replicate,
// independent of every pool). Per iteration each cache point gets a PMF over the candidates,
//     P_c(i) = q_c(i) / Σ_j q_c(j),   q_c(i) = max channel of β(x_i) f(x_i → y_c) G(x_i, y_c)
//     V_c(i),
// the light subpath's contribution towards y_c without the camera-side BSDF, V_c(i) = 1 when
// y_c sees x_i and `floor` when not (0: exact). A camera vertex y_{t-1} (t >= 2) finds its Nc
// nearest cache points C (kd-tree, estimators/scene/cache_points.h) and draws K candidates from
//     p(i) = u / N_v + (1 - u) / |C| Σ_{c∈C} P_c(i)
// (a cache point that sees nothing counts as uniform), each connection weighted 1 / (K M p(i)):
//     <I_j> = Σ_t [ w_{0,t} f / p_{0,t} + w_{1,t} f / p_{1,t} (nee=fresh)
//                   + Σ_{k<K} 1/(K M p(ξ_k)) w_{s_k,t} f / p_{s_k,t} ] + lt,
// where nee=fresh's next event connects y_{t-1} to an emitter vertex drawn for it alone, as path
// tracing does (under nee=draws the emitter vertices are candidates like any other). Unbiased
// wherever p > 0 where f > 0: always with u > 0. The balance weights count K samples per
// connection strategy (and per next-event strategy under nee=draws, 1 under nee=fresh), 1 per
// emitter hit and the pool size for light tracing (mis=balance), or, per connection strategy, the
// draws' effective samples of the path's light vertex from the previous iteration's tables
// (mis=resampling, resampling_counts.h; docs/findings/pcbpt-equal-time.md gives the measurements
// that keep it off by default).
//
// Every choice is a parameter (PcbptConfig, pcbpt.h; pcbpt_form.cpp declares them): M (128), K
// (8), uniform_mix u (0.25), cache every-depth|tile-first-hit, grid (16), tile (8), lookup
// nearest|tile|exact, Nc (3), guide first|all, cache_importance light|connection|weighted,
// visibility cache-point|ignored, floor (0.02), nee fresh|draws, light_tracing M|pixels, mis
// balance|resampling. Two named configurations (pcbpt_form.cpp; `pcbench list` gives their
// parameters): `published`, the published design (public sources: cache points at every depth
// from a grid of about 1/16 of the pixels per axis, three nearest cache points and a uniform
// share of 0.25, importance without the camera-side BSDF, occluded entries scaled by 0.02;
// docs/guide/scenes.md, "pcbpt's parameters"), from which the defaults depart in four choices on
// measurement; and `legacy-tile`, the tile design pcbench had before, bit for bit: one cache
// point per tile at the first hit, its P mixed with uniform, deeper vertices uniform
// (guide=first).
#include "estimators/scene/pcbpt.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "base/discrete_sampler.h"
#include "base/errors.h"
#include "estimators/resampling_step.h"
#include "estimators/scene/cache_mixture.h"
#include "estimators/scene/cache_points.h"
#include "estimators/scene/light_importance_lanes.h"
#include "estimators/scene/resampling_counts.h"
#include "estimators/scene/vertex_draws.h"
#include "integrands/scenes/path_vertex.h"

namespace pcbench {
namespace scene {
namespace {

class ProbabilisticPass final : public ScenePass {
 public:
  ProbabilisticPass(const RenderServices& services, const PcbptConfig& config, PcbptFlaw flaw)
      : services_(services),
        config_(config),
        unseen_draw_nothing_(flaw == PcbptFlaw::kUnseenCachePointsDrawNothing),
        caches_(services, config.every_depth ? config.grid : config.tile, !config.every_depth) {
    if (config_.nearest_lookup()) nearest_.emplace(caches_.points());
    if (config_.resampling_mis) {
      resampling_counts_.emplace(caches_.points(), m(), config_.draws, config_.uniform_mix,
                                 !config_.nee_fresh);
    }
  }

  void prepare(const LightPool& pool, TraceCounters& counters) override {
    // The counts of this iteration's weights come from the previous iteration's tables.
    if (resampling_counts_ && !totals_.empty()) {
      resampling_counts_->learn(totals_, static_cast<std::uint32_t>(vertices_.size()));
    }
    vertices_ = light_vertices(pool);
    // The candidates are the first M paths' vertices (light_vertices lists them path by path).
    const auto first_past = std::find_if(vertices_.begin(), vertices_.end(),
                                         [&](const LightVertexRef& v) { return v.path >= m(); });
    vertices_.erase(first_past, vertices_.end());
    // nee=fresh: next-event estimation has emitter vertices of its own; the pool's are not drawn.
    if (config_.nee_fresh) {
      std::erase_if(vertices_, [](const LightVertexRef& v) { return v.count == 1; });
    }
    candidates_.assign(services_.scene(), pool, vertices_);
    if (config_.lookup != PcbptConfig::Lookup::kExact) build_distributions(pool, counters);
  }

  const ConnectionCountModel* count_model() const override {
    return resampling_counts_ ? &*resampling_counts_ : nullptr;
  }

  // Every connection is queued (ConnectionQueue), the row's shadow rays traced as packets.
  bool queues_connections() const override { return true; }
  void queue_connections(const LightPool& pool, CameraPrefix& prefix,
                         ConnectionQueue& queue) const override {
    if (!config_.nee_fresh) return queue_drawn(pool, prefix, queue);
    // nee=fresh: an emitter vertex of its own for the camera vertex, drawn as a light subpath's
    // first vertex is (sample_emitter_vertex) from the pixel's camera stream where its subpath
    // left it, as path tracing does: independent of the pool and of every other pixel. The
    // draws' connections add up on their own before they join it.
    queue.connect_emitter_sample(prefix.camera, prefix);
    // Every candidate has s >= 2: none fits a prefix with room for one light vertex only.
    if (prefix.max_s < 2) return;
    queue.begin_subtotal(prefix);
    queue_drawn(pool, prefix, queue);
  }

 private:
  std::uint32_t m() const { return config_.light_paths; }

  // The K draws among the candidates and their connections.
  void queue_drawn(const LightPool& pool, CameraPrefix& prefix, ConnectionQueue& queue) const {
    if (vertices_.empty()) return;
    if (config_.lookup == PcbptConfig::Lookup::kNearest) {
      return queue_from_mixture(pool, prefix, queue);
    }
    if (config_.lookup == PcbptConfig::Lookup::kExact) return queue_exact(pool, prefix, queue);
    // lookup=tile: the block's cache point at this depth; deeper than its cache path, the first
    // hit's (guide=all) or a uniform draw, as the light vertex cache does.
    const std::uint32_t block = caches_.block_of(prefix.pixel);
    std::optional<std::uint32_t> cache = caches_.at(block, prefix.t() - 1);
    if (!cache && config_.guide_all) cache = caches_.at(block, 1);
    if (!cache) {
      return queue_drawn_vertices(pool, vertices_, prefix, config_.draws,
                                  uniform_vertex_draw(vertices_.size(), m(), config_.draws), queue);
    }
    const std::vector<double>& pmf = caches_at_[*cache].pmf;
    if (pmf.empty()) return;
    const double k = config_.draws;
    const double paths = m();
    const DiscreteSampler& sampler = caches_at_[*cache].sampler;
    queue_drawn_vertices(
        pool, vertices_, prefix, config_.draws,
        [&](RandomStream& draws) {
          const std::uint32_t index = sampler.draw(draws);
          return VertexDraw{index, 1.0 / (k * paths * pmf[index])};
        },
        queue);
  }

  // K draws from the mixture of the nearest cache points' P and the uniform share, each
  // weighted by the mixture's exact PMF (cache_mixture.h).
  void queue_from_mixture(const LightPool& pool, CameraPrefix& prefix,
                          ConnectionQueue& queue) const {
    std::uint32_t near[NearestCachePoints::kMaxFound];
    const std::uint32_t found =
        nearest_->find(prefix.vertices.back().position, config_.nearest, near);
    queue_drawn_from(
        pool, prefix,
        CacheMixture(caches_at_, std::span<const std::uint32_t>(near, found),
                     static_cast<std::uint32_t>(vertices_.size()), config_.uniform_mix),
        queue);
  }

  // lookup=exact: the camera vertex as its own cache point, its P built here over every
  // candidate (shadow rays included), mixed with the uniform share as the nearest lookup does.
  void queue_exact(const LightPool& pool, CameraPrefix& prefix, ConnectionQueue& queue) const {
    const CachePoint here{.camera = Subpath(prefix.vertices.begin(), prefix.vertices.end()),
                          .depth = prefix.t() - 1};
    CacheDistribution own;
    ImportanceScratch& scratch = scratch_.local();
    importance_at(pool, here, scratch, prefix.counters);
    const std::vector<double>& q = scratch.importances.q;
    double total = 0.0;
    for (double w : q) total += w;
    if (total > 0.0) {
      own.pmf.resize(q.size());
      for (std::size_t i = 0; i < q.size(); ++i) own.pmf[i] = q[i] / total;
      own.sampler.build(own.pmf, DiscreteSamplerKind::kCdf);
    }
    const std::uint32_t self = 0;
    queue_drawn_from(
        pool, prefix,
        CacheMixture(std::span<const CacheDistribution>(&own, 1),
                     std::span<const std::uint32_t>(&self, 1),
                     static_cast<std::uint32_t>(vertices_.size()), config_.uniform_mix),
        queue);
  }

  // K draws from `mixture`, each weighted by its exact PMF (cache_mixture.h). A batch of draws is
  // made, then their PMFs: the draws' and the PMFs' lookups in the cache points' tables (caches ×
  // N_v entries, several MB) are cache misses, independent of each other within a step, which
  // then overlap rather than each wait behind the last.
  void queue_drawn_from(const LightPool& pool, CameraPrefix& prefix, const CacheMixture& mixture,
                        ConnectionQueue& queue) const {
    const double k = config_.draws;
    const double paths = m();
    constexpr auto kBatch = static_cast<std::uint32_t>(CacheMixture::kMaxMany);
    std::optional<std::uint32_t> index[kBatch];
    VertexDraw batch[kBatch];
    for (std::uint32_t first = 0; first < config_.draws; first += kBatch) {
      const std::uint32_t size = std::min(kBatch, config_.draws - first);
      mixture.draw_many(prefix.draws, unseen_draw_nothing_, std::span(index, size));
      for (std::uint32_t d = 0; d < size; ++d) {
        if (!index[d]) {
          batch[d] = VertexDraw{0, 0.0};
        } else if (vertices_[*index[d]].count > prefix.max_s) {
          batch[d] = VertexDraw{*index[d], 0.0};  // not connected: its coefficient is not used
        } else {
          batch[d] = VertexDraw{*index[d], 1.0 / (k * paths * mixture.pmf(*index[d]))};
        }
      }
      queue_vertex_draws(pool, vertices_, prefix, std::span(batch, size), queue);
    }
  }

  // A table's working space, one per thread, kept from one cache point and one iteration to the
  // next: allocated per cache point, its shadow rays alone were up to 320 KB at M = 1024, and
  // freeing them and faulting their pages in again was 8% of the published design's run.
  struct ImportanceScratch {
    LightImportances importances;  // q_c(i) in importances.q
    std::vector<Scene::ShadowRay> rays;
    std::vector<std::uint32_t> ray_of;  // the candidate each ray decides
    std::vector<std::uint8_t> blocked;
  };

  // q_c(i) for every candidate at cache point c, into scratch.importances.q; the shadow rays are
  // counted as connect() counts its own (skipped in a convex enclosure, where nothing is
  // occluded). The rays of the candidates with q > 0 share their end at c and are traced together
  // as Embree packets (Scene::occluded_many): one at a time they were a third of pcbpt's rays.
  void importance_at(const LightPool& pool, const CachePoint& cache, ImportanceScratch& scratch,
                     TraceCounters& counters) const {
    const Scene& scene = services_.scene();
    // The light importance and every candidate's segment, in lanes (light_importance_lanes.h);
    // the other importances replace q with the connection's value.
    LightImportances& at = scratch.importances;
    candidates_.at(scene, cache.vertex(), at);
    std::vector<double>& q = at.q;
    if (config_.importance != PcbptConfig::Importance::kLight) {
      const ConnectOptions unoccluded{
          .visibility = false,
          .weighted = config_.importance == PcbptConfig::Importance::kWeighted};
      for (std::uint32_t i = 0; i < q.size(); ++i) {
        q[i] =
            services_.connect(light_prefix(pool, vertices_[i]), cache.camera, unoccluded, counters)
                .max_channel();
      }
    }
    if (!config_.cache_visibility) return;
    const bool traces = !scene.traits().convex_enclosure;
    scratch.rays.clear();
    scratch.ray_of.clear();
    for (std::uint32_t i = 0; i < q.size(); ++i) {
      if (!(q[i] > 0.0)) continue;
      if (!traces) {
        ++counters.skipped_convex;
        continue;
      }
      scratch.rays.push_back(scene.shadow_ray(candidates_.position(i), cache.vertex().position,
                                              at.distance_squared[i], at.distance[i]));
      scratch.ray_of.push_back(i);
    }
    if (scratch.rays.empty()) return;
    scratch.blocked.resize(scratch.rays.size());
    scene.occluded_many(scratch.rays, scratch.blocked);
    counters.shadow_rays += scratch.rays.size();
    for (std::size_t k = 0; k < scratch.rays.size(); ++k) {
      if (!scratch.blocked[k]) continue;
      ++counters.occluded;
      q[scratch.ray_of[k]] *= config_.visibility_floor;
    }
  }

  void build_distributions(const LightPool& pool, TraceCounters& counters) {
    const std::span<const CachePoint> points = caches_.points();
    const std::size_t caches = points.size();
    const auto n = static_cast<std::uint32_t>(vertices_.size());
    // The tables of the last iteration keep their memory: only their P is cleared (a cache point
    // without one counts as uniform).
    caches_at_.resize(caches);
    for (CacheDistribution& c : caches_at_) c.pmf.clear();
    totals_.assign(caches, 0.0);
    if (n == 0) return;
    // lookup=tile mixes the uniform share into each P; the nearest lookup mixes at draw time.
    const ResamplingStep step(
        StepConfig{.M = n,
                   .K = config_.draws,
                   .selection = Selection::kImportance,
                   .scheme = DrawScheme::kIndependent,
                   .uniform_mix = config_.nearest_lookup() ? 0.0 : config_.uniform_mix,
                   .sampler = DiscreteSamplerKind::kAlias});
    std::vector<TraceCounters> cache_counters(caches);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, caches), [&](const auto& range) {
      ImportanceScratch& scratch = scratch_.local();
      for (std::size_t c = range.begin(); c != range.end(); ++c) {
        std::vector<double>& q = scratch.importances.q;
        if (points[c].camera.empty()) {
          q.assign(n, 0.0);
        } else {
          importance_at(pool, points[c], scratch, cache_counters[c]);
        }
        double total = 0.0;
        for (double w : q) total += w;
        totals_[c] = total;
        if (total == 0.0) {
          // The nearest lookup counts it as uniform; lookup=tile mixes zero with uniform, except
          // in the control, whose tile then draws nothing (its bias).
          if (config_.nearest_lookup() || unseen_draw_nothing_) continue;
        }
        step.build_pmf(PoolView{.importance = q}, caches_at_[c].pmf);
        caches_at_[c].sampler.build(caches_at_[c].pmf, DiscreteSamplerKind::kAlias);
      }
    });
    for (const TraceCounters& c : cache_counters) counters.add(c);
  }

  const RenderServices& services_;
  PcbptConfig config_;
  bool unseen_draw_nothing_;  // the control's flaw (PcbptFlaw, pcbpt.h)
  CachePoints caches_;
  std::optional<NearestCachePoints> nearest_;
  // Per iteration: the candidates and, per cache point, P over them and its sampler (none when it
  // sees nothing, except under lookup=tile, which mixes zero with uniform).
  std::vector<LightVertexRef> vertices_;
  LightImportanceLanes candidates_;  // their terms of the light importance
  mutable tbb::enumerable_thread_specific<ImportanceScratch> scratch_;
  std::vector<CacheDistribution> caches_at_;
  // mis=resampling: the counts, and Σ_i q_c(i) per cache point of the latest tables.
  std::optional<ResamplingCounts> resampling_counts_;
  std::vector<double> totals_;
};

class Probabilistic final : public SceneEstimator {
 public:
  Probabilistic(const PcbptConfig& config, PcbptFlaw flaw) : config_(config), flaw_(flaw) {}

  std::uint32_t pool_size(const Scene& scene) const override {
    if (!config_.light_tracing_pixels) return config_.light_paths;
    return std::max(config_.light_paths, scene.description().width * scene.description().height);
  }
  StrategyCounts strategy_counts(const Scene& scene) const override {
    StrategyCounts counts = vertex_draw_counts(config_.light_paths, config_.draws);
    counts.light_tracing = pool_size(scene);
    if (config_.nee_fresh) counts.next_event = 1.0;  // one emitter vertex per camera vertex
    return counts;
  }
  std::unique_ptr<ScenePass> begin_replicate(const RenderServices& services) const override {
    return std::make_unique<ProbabilisticPass>(services, config_, flaw_);
  }

 private:
  PcbptConfig config_;
  PcbptFlaw flaw_;
};

}  // namespace

std::shared_ptr<const SceneEstimator> make_pcbpt(const PcbptConfig& config, PcbptFlaw flaw) {
  return std::make_shared<Probabilistic>(config, flaw);
}

}  // namespace scene
}  // namespace pcbench

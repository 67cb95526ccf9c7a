// restir (scenes): ris (ris.cpp) with spatial reuse of the first camera vertex's reservoirs
// (Bitterli et al. 2020), weighted as generalized RIS prescribes (Lin et al. 2022).
//
// Each iteration, every pixel c resamples M emitter points at its first vertex y_1 (prefix t = 2)
// into a reservoir (Y_c, W_c) as ris does. Then, for each of `rounds` rounds, pixel c draws N
// pixels uniformly in the disk of `radius` pixels around it (off-image and cameras rays that left
// no vertex dropped) and streams the sources S = {c, n_1 .. n_k} into a new reservoir, source s
// with weight
//     w_s = m_s(Y_s) p̂_c(Y_s) W_s,   W_c' = Σ_s w_s / p̂_c(Y'),
// m_s from reuse_weights.h over the sources' targets T_t = p̂_t(Y_s) (balance, pairwise, count).
// Its next event at y_1 is f_w(Y') W_c'. Deeper vertices (t >= 3) take ris's next event; the
// emitter hits and MIS counts are ris's.
// Why it is unbiased: given every pixel's prefix, each source's (Y_s, W_s) is an unbiased
// contribution weight for the support of its own target (a ris reservoir, or an earlier round's
// reuse, which covers its pixel's support), and the neighbours are drawn independently of the
// samples; so E[Σ_s m_s(Y_s) f_c(Y_s) W_s] = ∫ f_c Σ_{s: p̂_s > 0} m_s, which is ∫ f_c when the
// weights sum to 1 over the sources that can produce x. Two conditions, each the mistake of a
// control (ctl_scene_naive_reuse.cpp, ctl_scene_reuse_unshadowed.cpp): the weights must see the
// same support as the sources (targets with visibility if the reservoirs have it), and must not
// give a share to a source that cannot produce x (1/(k+1) does).
// Parameters: M, target (as ris), N (1–32), radius (pixels, 10), rounds (1–4, 2), weights
// (balance, pairwise, count).
#include "estimators/scene/restir.h"

#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "estimators/reservoir.h"
#include "estimators/reservoir_estimator.h"
#include "estimators/reservoir_params.h"

namespace pcbench::scene {
namespace {

constexpr std::size_t kMaxSources = kMaxReuseNeighbours + 1;  // the pixel and its neighbours
static_assert(kMaxSources <= EmitterPoints::kCapacity);
using SourceArray = std::array<std::uint32_t, kMaxSources>;
using TargetArray = std::array<double, kMaxSources>;

// A pixel's camera prefix y_0 y_1, where its next event is reused.
struct FirstVertex {
  std::array<PathVertex, 2> prefix = {};
  bool valid = false;  // a camera vertex with a next event: its connections ran at t = 2
};

class RestirPass final : public ScenePass {
 public:
  RestirPass(const RenderServices& services, const SceneRestirConfig& config)
      : services_(services),
        config_(config),
        weight_target_(config.weights_without_visibility ? EmitterTarget::kUnshadowed
                                                         : config.ris.target),
        pixels_(services.width() * services.height()),
        first_(pixels_),
        valid_(pixels_),
        current_(pixels_),
        next_(pixels_) {}

  void prepare(const LightPool&, TraceCounters&) override {
    std::fill(first_.begin(), first_.end(), FirstVertex{});
    std::fill(valid_.begin(), valid_.end(), std::uint8_t{0});
    std::fill(current_.begin(), current_.end(), EmitterSample{});
  }

  // As ris's (ris.cpp): the unshadowed target's samples of t > 2 queued, the visible target's
  // shaded at once.
  bool queues_connections() const override {
    return config_.ris.target == EmitterTarget::kUnshadowed;
  }
  void queue_connections(const LightPool&, CameraPrefix& prefix,
                         ConnectionQueue& queue) const override {
    const EmitterSample y =
        resample_emitters(services_, prefix, config_.ris.candidates, config_.ris.target);
    if (!kept_for_reuse(prefix, y)) queue_emitter_sample(y, prefix, queue);
  }

  Rgb connections(const LightPool&, CameraPrefix& prefix) const override {
    const EmitterSample y =
        resample_emitters(services_, prefix, config_.ris.candidates, config_.ris.target);
    if (kept_for_reuse(prefix, y)) return {};
    const Rgb value = shade_emitter_sample(services_, y.point, y.at_owner, y.contribution_weight,
                                           prefix.vertices, config_.ris.target, prefix.counters);
    services_.record(1, prefix, value);
    return value;
  }

  void finish_iteration(std::uint32_t index, Image& sum, TraceCounters& counters) override {
    for (std::uint32_t round = 0; round < config_.rounds; ++round) {
      for_rows(counters, [&](std::uint32_t pixel, TraceCounters& row) {
        next_[pixel] = reuse(pixel, index, round, row);
      });
      std::swap(current_, next_);
    }
    for_rows(counters, [&](std::uint32_t pixel, TraceCounters& row) {
      const FirstVertex& own = first_[pixel];
      if (!own.valid) return;
      const EmitterSample& y = current_[pixel];
      const Rgb value = shade_emitter_sample(services_, y.point, y.at_owner, y.contribution_weight,
                                             own.prefix, config_.ris.target, row);
      sum.values[3 * std::size_t{pixel} + 0] += value.r;
      sum.values[3 * std::size_t{pixel} + 1] += value.g;
      sum.values[3 * std::size_t{pixel} + 2] += value.b;
      services_.record(1, 2, pixel, value);
    });
  }

 private:
  // The first vertex's sample (t = 2) is kept in this pixel's slots, reused in finish_iteration
  // and shaded there; true when `prefix` is that vertex's.
  bool kept_for_reuse(const CameraPrefix& prefix, const EmitterSample& y) const {
    if (prefix.t() != 2) return false;
    first_[prefix.pixel] = {{prefix.vertices[0], prefix.vertices[1]}, true};
    valid_[prefix.pixel] = 1;
    current_[prefix.pixel] = y;
    return true;
  }

  // `each(pixel, row counters)` for every pixel, rows in parallel; the counters summed in row
  // order.
  template <typename Each>
  void for_rows(TraceCounters& counters, const Each& each) const {
    const std::uint32_t width = services_.width(), height = services_.height();
    std::vector<TraceCounters> rows(height);
    tbb::parallel_for(std::uint32_t{0}, height, [&](std::uint32_t y) {
      for (std::uint32_t x = 0; x < width; ++x) each(y * width + x, rows[y]);
    });
    for (const TraceCounters& row : rows) counters.add(row);
  }

  // The pixels `pixel` resamples from in `round`: itself, then up to N drawn in the disk.
  std::size_t draw_sources(std::uint32_t pixel, RandomStream& rng, SourceArray& sources) const {
    const int width = static_cast<int>(services_.width());
    const int height = static_cast<int>(services_.height());
    const int x = static_cast<int>(pixel) % width, y = static_cast<int>(pixel) / width;
    std::size_t count = 0;
    sources[count++] = pixel;
    for (std::uint32_t n = 0; n < config_.neighbours; ++n) {
      const double r = config_.radius * std::sqrt(rng.uniform());
      const double phi = 2.0 * kPi * rng.uniform();
      const int nx = x + static_cast<int>(std::lround(r * std::cos(phi)));
      const int ny = y + static_cast<int>(std::lround(r * std::sin(phi)));
      if ((nx == x && ny == y) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      const std::uint32_t neighbour = static_cast<std::uint32_t>(ny * width + nx);
      if (!valid_[neighbour]) continue;
      sources[count++] = neighbour;
      // Its vertex is read for the weights' targets after this pixel's own: started now.
      __builtin_prefetch(&first_[neighbour].prefix[1]);
      __builtin_prefetch(&current_[neighbour]);
    }
    return count;
  }

  // One round's reservoir of `pixel`, from the previous round's (current_). Every target the
  // round reads is weighed one camera prefix at a time, each prefix's samples together
  // (emitter_targets): p̂_c(Y_s) of every source's sample at this pixel, then T_t = p̂_t(Y_s)
  // for the weights, at source t's prefix for every sample s that reads it. The same targets
  // and counters as one pair at a time, without a prefix set up and a batch weighed per pair.
  EmitterSample reuse(std::uint32_t pixel, std::uint32_t index, std::uint32_t round,
                      TraceCounters& counters) const {
    const FirstVertex& own = first_[pixel];
    if (!own.valid) return {};
    RandomStream rng(
        services_.stream(StreamPurpose::kEstimatorAux, index, round * pixels_ + pixel));
    SourceArray sources;
    const std::size_t count = draw_sources(pixel, rng, sources);

    // p̂_c(Y_s) for the sources that hold a sample.
    // Written for the sources that hold a sample, and read only for those (not zeroed: a
    // kilobyte zeroed per pixel and round was a tenth of the round).
    std::array<EmitterTargetValue, kMaxSources> at_own;
    std::array<const PathVertex*, kMaxSources> points;
    std::array<std::size_t, kMaxSources> source_of;
    std::size_t held = 0;
    for (std::size_t s = 0; s < count; ++s) {
      if (current_[sources[s]].empty()) continue;
      points[held] = &current_[sources[s]].point;
      source_of[held++] = s;
    }
    {
      std::array<EmitterTargetValue, kMaxSources> values;
      emitter_targets(services_, std::span(points).first(held), own.prefix, config_.ris.target,
                      std::span(values).first(held), counters);
      for (std::size_t k = 0; k < held; ++k) at_own[source_of[k]] = values[k];
    }

    // targets[s][t] = T_t(Y_s) for the sources whose sample has p̂_c > 0 (the others are not
    // offered): as one source's sample kept it, or as this pixel's own target has it, where the
    // weights' targets are those; not read by pairwise weights of a neighbour's sample except
    // at c and s; weighed at t's prefix otherwise.
    const bool same_target = weight_target_ == config_.ris.target;
    const auto offered = [&](std::size_t s) {
      return !current_[sources[s]].empty() && at_own[s].density > 0.0;
    };
    const auto weighed = [&](std::size_t s, std::size_t t) {
      if (same_target && (t == 0 || t == s)) return false;
      const bool pair_only = config_.weighting.form == ReuseWeights::kPairwise && s != 0;
      return !(pair_only && t != 0 && t != s);
    };
    std::array<TargetArray, kMaxSources> targets;
    for (std::size_t s = 0; s < count; ++s) {
      if (!offered(s)) continue;
      for (std::size_t t = 0; t < count; ++t) {
        targets[s][t] = same_target && t == 0   ? at_own[s].density
                        : same_target && t == s ? current_[sources[s]].at_owner.density
                                                : 0.0;
      }
    }
    for (std::size_t t = 0; t < count; ++t) {
      std::size_t n = 0;
      for (std::size_t s = 0; s < count; ++s) {
        if (!offered(s) || !weighed(s, t)) continue;
        points[n] = &current_[sources[s]].point;
        source_of[n++] = s;
      }
      std::array<EmitterTargetValue, kMaxSources> values;
      emitter_targets(services_, std::span(points).first(n), first_[sources[t]].prefix,
                      weight_target_, std::span(values).first(n), counters);
      for (std::size_t k = 0; k < n; ++k) targets[source_of[k]][t] = values[k].density;
    }

    Reservoir reservoir;
    EmitterSample kept;
    for (std::size_t s = 0; s < count; ++s) {
      if (!offered(s)) continue;
      const EmitterSample& from = current_[sources[s]];
      const double m = reuse_mis_weight(config_.weighting, std::span(targets[s]).first(count), s);
      reservoir.offer(static_cast<std::uint32_t>(s),
                      m * at_own[s].density * from.contribution_weight, rng);
      if (reservoir.kept() == s) {
        kept.point = from.point;
        kept.at_owner = at_own[s];
      }
    }
    if (!reservoir.empty()) {
      kept.contribution_weight = reservoir.weight_sum() / kept.at_owner.density;
    }
    return kept;
  }

  const RenderServices& services_;
  SceneRestirConfig config_;
  EmitterTarget weight_target_;  // the targets the reuse weights are computed from
  std::uint32_t pixels_;
  // Written by connections() at each pixel's own slot (t = 2), read by finish_iteration().
  mutable std::vector<FirstVertex> first_;
  // first_[p].valid alone, compact: the neighbours drawn are tested against it, and a
  // FirstVertex a cache miss away was a third of a reuse round (perf, many-lights 128²).
  mutable std::vector<std::uint8_t> valid_;
  mutable std::vector<EmitterSample> current_;
  std::vector<EmitterSample> next_;
};

class Restir final : public SceneEstimator {
 public:
  explicit Restir(const SceneRestirConfig& config) : config_(config) {}

  std::uint32_t pool_size(const Scene&) const override { return 0; }
  StrategyCounts strategy_counts(const Scene&) const override {
    return next_event_counts(config_.ris.candidates);
  }
  bool samples_all_paths(const Scene& scene) const override { return !needs_light_subpaths(scene); }
  std::unique_ptr<ScenePass> begin_replicate(const RenderServices& services) const override {
    return std::make_unique<RestirPass>(services, config_);
  }

 private:
  SceneRestirConfig config_;
};

}  // namespace

std::shared_ptr<const SceneEstimator> make_scene_restir(const SceneRestirConfig& config) {
  return std::make_shared<Restir>(config);
}

}  // namespace pcbench::scene

namespace pcbench {

ParamSpec reuse_neighbours_spec() {
  return {.name = "N",
          .type = ParamType::kInt,
          .default_value = "4",
          .description = "pixels drawn uniformly in the disk per reuse round",
          .min = 1,
          .max = kMaxReuseNeighbours};
}

ParamSpec reuse_radius_spec() {
  return {.name = "radius",
          .type = ParamType::kInt,
          .default_value = "10",
          .description = "radius of the reuse disk, in pixels",
          .min = 1,
          .max = 256};
}

ParamSpec reuse_rounds_spec() {
  return {.name = "rounds",
          .type = ParamType::kInt,
          .default_value = "2",
          .description = "rounds of spatial reuse, each from the previous round's reservoirs",
          .min = 1,
          .max = 4};
}

void read_scene_restir_params(const ResolvedParams& params, scene::SceneRestirConfig& config) {
  read_scene_ris_params(params, config.ris);
  if (params.has("N")) config.neighbours = static_cast<std::uint32_t>(params.integer("N"));
  if (params.has("radius")) config.radius = static_cast<std::uint32_t>(params.integer("radius"));
  if (params.has("rounds")) config.rounds = static_cast<std::uint32_t>(params.integer("rounds"));
  if (params.has("weights")) config.weighting.form = reuse_weights_named(params.text("weights"));
}

SceneForm restir_scene_form() {
  return {.params = {emitter_candidates_spec(16), emitter_target_spec(), reuse_neighbours_spec(),
                     reuse_radius_spec(), reuse_rounds_spec(), reuse_weights_spec()},
          .make = [](const ResolvedParams& params) {
            scene::SceneRestirConfig config;
            read_scene_restir_params(params, config);
            return scene::make_scene_restir(config);
          }};
}

scene::SceneRestirConfig reuse_control_config(const ResolvedParams& params) {
  scene::SceneRestirConfig config;
  config.ris.target = scene::EmitterTarget::kVisible;
  read_scene_restir_params(params, config);
  return config;
}

std::vector<ParamSpec> reuse_control_params() {
  return {emitter_candidates_spec(16), reuse_neighbours_spec(), reuse_radius_spec()};
}

DeclaredWorkload reuse_control_workload() {
  return {.integrand = "cornell",
          .integrand_params = {{"resolution", "64"}},
          .samples = 8,
          .replicates = 16,
          .partners = {"pt"}};
}

}  // namespace pcbench

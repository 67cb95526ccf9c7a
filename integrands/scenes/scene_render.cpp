#include "integrands/scenes/scene_render.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <chrono>
#include <ctime>
#include <vector>

#include "estimators/discrete_sampler.h"
#include "estimators/resampling_step.h"
#include "integrands/scenes/strategy_tally.h"

namespace pcbench::scene {
namespace {

using Subpath = std::vector<PathVertex>;

// Light subpaths per chunk of parallel work; splats are merged chunk by chunk in order.
constexpr std::uint32_t kLightChunk = 64;

struct LightVertexRef {
  std::uint32_t path = 0;
  std::uint32_t count = 0;  // s: the prefix x_0 .. x_{s-1} ends at this vertex
};

struct Splat {
  std::uint32_t pixel = 0;
  std::uint32_t s = 0;  // light vertices of the splatted prefix (strategy (s, 1))
  Rgb value = {};
};

double process_cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

std::uint32_t pool_size(const RenderConfig& config, const Scene& scene) {
  switch (config.method) {
    case Method::kPathTracing:
      return 0;
    case Method::kLightTracing:
    case Method::kBdpt:
      return scene.description().width * scene.description().height;
    default:
      return config.light_paths;
  }
}

// Everything one iteration shares between pixels.
struct Iteration {
  std::vector<Subpath> pool;
  std::vector<LightVertexRef> vertices;  // every vertex of the pool (lvc, pcbpt)
  // pcbpt: per tile, P over `vertices` and its sampler.
  std::vector<std::vector<double>> tile_pmf;
  std::vector<DiscreteSampler> tile_sampler;
  // One byte per tile, not std::vector<bool>: tiles are built in parallel, and the bits of a
  // vector<bool> share words, so two tiles' writes would race and one could be lost.
  std::vector<std::uint8_t> tile_has_draws;
};

class Renderer {
 public:
  // `strategies` (may be null) receives every contribution again, by strategy.
  Renderer(const Scene& scene, const RenderConfig& config, std::uint64_t key,
           std::uint32_t replicate, StrategyTally* strategies)
      : scene_(scene),
        config_(config),
        key_(key),
        replicate_(replicate),
        counts_(strategy_counts(config, scene)),
        width_(scene.description().width),
        height_(scene.description().height),
        max_length_(scene.description().max_length),
        tiles_x_((width_ + config.tile - 1) / config.tile),
        tiles_y_((height_ + config.tile - 1) / config.tile),
        strategies_(strategies) {
    if (config.method == Method::kProbabilistic) trace_cache_points();
  }

  void iterate(std::uint32_t index, Image& sum, TraceCounters& counters) {
    Iteration it;
    trace_pool(index, it, counters);
    if (config_.method == Method::kLightVertexCache || config_.method == Method::kProbabilistic) {
      for (std::uint32_t j = 0; j < it.pool.size(); ++j) {
        for (std::uint32_t s = 1; s <= it.pool[j].size(); ++s) it.vertices.push_back({j, s});
      }
    }
    if (config_.method == Method::kProbabilistic) build_tile_distributions(it, counters);
    if (config_.method != Method::kPathTracing) splat_pool(it, sum, counters);
    if (config_.method != Method::kLightTracing) camera_pass(index, it, sum, counters);
  }

 private:
  StreamId stream(StreamPurpose purpose, std::uint32_t sample, std::uint32_t path) const {
    return {
        .key = key_, .replicate = replicate_, .purpose = purpose, .sample = sample, .path = path};
  }

  void trace_pool(std::uint32_t index, Iteration& it, TraceCounters& counters) {
    const std::uint32_t m = pool_size(config_, scene_);
    it.pool.resize(m);
    const std::uint32_t chunks = (m + kLightChunk - 1) / kLightChunk;
    std::vector<TraceCounters> chunk_counters(chunks);
    tbb::parallel_for(std::uint32_t{0}, chunks, [&](std::uint32_t c) {
      for (std::uint32_t j = c * kLightChunk; j < std::min(m, (c + 1) * kLightChunk); ++j) {
        RandomStream rng(stream(StreamPurpose::kLightPool, index, j));
        trace_light_path(scene_, rng, max_length_, it.pool[j], chunk_counters[c]);
      }
    });
    for (const TraceCounters& c : chunk_counters) counters.add(c);
  }

  // Light tracing: every prefix of every pool path connects to the camera (t = 1).
  void splat_pool(const Iteration& it, Image& sum, TraceCounters& counters) {
    const std::uint32_t m = static_cast<std::uint32_t>(it.pool.size());
    const std::uint32_t chunks = (m + kLightChunk - 1) / kLightChunk;
    std::vector<std::vector<Splat>> splats(chunks);
    std::vector<TraceCounters> chunk_counters(chunks);
    const PathVertex camera_vertex = camera_start();
    tbb::parallel_for(std::uint32_t{0}, chunks, [&](std::uint32_t c) {
      for (std::uint32_t j = c * kLightChunk; j < std::min(m, (c + 1) * kLightChunk); ++j) {
        const Subpath& path = it.pool[j];
        for (std::uint32_t s = 1; s <= path.size() && s <= max_length_; ++s) {
          std::optional<PixelPosition> pixel;
          const Rgb v = connect(scene_, std::span(path).first(s), std::span(&camera_vertex, 1),
                                counts_, {}, chunk_counters[c], &pixel);
          if (!pixel || v.is_black()) continue;
          ++chunk_counters[c].splats;
          splats[c].push_back({pixel->y * width_ + pixel->x, s, v / m});
        }
      }
    });
    // In chunk order, so the sums do not depend on the thread count.
    for (std::uint32_t c = 0; c < chunks; ++c) {
      counters.add(chunk_counters[c]);
      for (const Splat& s : splats[c]) {
        add(sum, s.pixel, s.value);
        record(s.s, 1, s.pixel, s.value);
      }
    }
  }

  // The strategy images' share of a contribution already added to the image (nothing without
  // --strategy-images).
  void record(std::uint32_t s, std::uint32_t t, std::uint32_t pixel, const Rgb& value) const {
    if (strategies_ != nullptr) strategies_->add(s, t, pixel, value);
  }

  PathVertex camera_start() const {
    PathVertex y0;
    y0.kind = VertexKind::kCamera;
    y0.position = scene_.camera().position();
    y0.beta = {1.0, 1.0, 1.0};
    return y0;
  }

  static void add(Image& image, std::uint32_t pixel, const Rgb& v) {
    image.values[3 * std::size_t{pixel} + 0] += v.r;
    image.values[3 * std::size_t{pixel} + 1] += v.g;
    image.values[3 * std::size_t{pixel} + 2] += v.b;
  }

  void camera_pass(std::uint32_t index, const Iteration& it, Image& sum, TraceCounters& counters) {
    std::vector<TraceCounters> row_counters(height_);
    tbb::parallel_for(std::uint32_t{0}, height_, [&](std::uint32_t y) {
      Subpath camera;
      Subpath emitter(1);
      for (std::uint32_t x = 0; x < width_; ++x) {
        const std::uint32_t pixel = y * width_ + x;
        RandomStream rng(stream(StreamPurpose::kCameraPath, index, pixel));
        const double fx = x + rng.uniform(), fy = y + rng.uniform();
        trace_camera_path(scene_, fx, fy, rng, max_length_, camera, row_counters[y]);
        RandomStream draws(stream(StreamPurpose::kResampling, index, pixel));
        Rgb value;
        for (std::uint32_t t = 2; t <= camera.size(); ++t) {
          const auto prefix = std::span<const PathVertex>(camera).first(t);
          const Rgb emitter_hit = connect(scene_, {}, prefix, counts_, {}, row_counters[y]);
          value += emitter_hit;
          record(0, t, pixel, emitter_hit);
          value += connections(it, pixel, prefix, rng, draws, emitter, row_counters[y]);
        }
        add(sum, pixel, value);
      }
    });
    for (const TraceCounters& c : row_counters) counters.add(c);
  }

  // The connections of camera prefix y_0 .. y_{t-1} (t >= 2) with light vertices.
  Rgb connections(const Iteration& it, std::uint32_t pixel, std::span<const PathVertex> camera,
                  RandomStream& rng, RandomStream& draws, Subpath& emitter,
                  TraceCounters& counters) const {
    const std::uint32_t t = static_cast<std::uint32_t>(camera.size());
    if (t > max_length_) return {};  // no room for a light vertex
    const std::uint32_t max_s = max_length_ + 1 - t;
    Rgb value;
    // `share` scales what the strategy images receive: the value's part of the returned sum.
    auto connect_to = [&](const Subpath& path, std::uint32_t s, double share = 1.0) {
      const Rgb v = connect(scene_, std::span(path).first(s), camera, counts_, {}, counters);
      record(s, t, pixel, share == 1.0 ? v : v * share);
      return v;
    };
    switch (config_.method) {
      case Method::kPathTracing:
        emitter[0] = sample_emitter_vertex(scene_, rng);
        return connect_to(emitter, 1);
      case Method::kLightTracing:
        return {};
      case Method::kBdpt: {
        const Subpath& path = it.pool[pixel];
        for (std::uint32_t s = 1; s <= std::min<std::uint32_t>(max_s, path.size()); ++s) {
          value += connect_to(path, s);
        }
        return value;
      }
      case Method::kVertexConnection: {
        const double per_path = 1.0 / static_cast<double>(it.pool.size());
        for (const Subpath& path : it.pool) {
          for (std::uint32_t s = 1; s <= std::min<std::uint32_t>(max_s, path.size()); ++s) {
            value += connect_to(path, s, per_path);
          }
        }
        return value / static_cast<double>(it.pool.size());
      }
      case Method::kLightVertexCache:
      case Method::kProbabilistic:
        return resampled(it, pixel, camera, max_s, draws, counters);
    }
    return {};
  }

  Rgb resampled(const Iteration& it, std::uint32_t pixel, std::span<const PathVertex> camera,
                std::uint32_t max_s, RandomStream& draws, TraceCounters& counters) const {
    const std::size_t vertex_count = it.vertices.size();
    if (vertex_count == 0) return {};
    const double m = static_cast<double>(it.pool.size());
    const double k = config_.draws;
    // The tile's cache point stands for the first camera vertex only (unless guide_all): deeper
    // vertices lie elsewhere and draw uniformly, as the light vertex cache does.
    const bool uniform =
        config_.method == Method::kLightVertexCache || (!config_.guide_all && camera.size() > 2);
    const std::uint32_t tile = tile_of(pixel);
    if (!uniform && !it.tile_has_draws[tile]) return {};
    Rgb value;
    for (std::uint32_t d = 0; d < config_.draws; ++d) {
      std::uint32_t index = 0;
      double coefficient = 0.0;
      if (uniform) {
        index = draws.uniform_index(static_cast<std::uint32_t>(vertex_count));
        coefficient = config_.flaw == SceneFlaw::kPerVertexNormalisation
                          ? 1.0 / k
                          : static_cast<double>(vertex_count) / (k * m);
      } else {
        index = it.tile_sampler[tile].draw(draws);
        coefficient = 1.0 / (k * m * it.tile_pmf[tile][index]);
      }
      const LightVertexRef& v = it.vertices[index];
      if (v.count > max_s) continue;
      const Rgb drawn = coefficient * connect(scene_, std::span(it.pool[v.path]).first(v.count),
                                              camera, counts_, {}, counters);
      value += drawn;
      record(v.count, static_cast<std::uint32_t>(camera.size()), pixel, drawn);
    }
    return value;
  }

  std::uint32_t tile_of(std::uint32_t pixel) const {
    const std::uint32_t x = pixel % width_, y = pixel / width_;
    return (y / config_.tile) * tiles_x_ + x / config_.tile;
  }

  // pcbpt's cache points: the first hit through each tile's centre (fixed for the whole run, so
  // the guidance does not depend on any pool).
  void trace_cache_points() {
    TraceCounters ignored;
    cache_paths_.resize(std::size_t{tiles_x_} * tiles_y_);
    for (std::uint32_t ty = 0; ty < tiles_y_; ++ty) {
      for (std::uint32_t tx = 0; tx < tiles_x_; ++tx) {
        const double cx = std::min<double>(width_, (tx + 0.5) * config_.tile);
        const double cy = std::min<double>(height_, (ty + 0.5) * config_.tile);
        RandomStream unused(stream(StreamPurpose::kEstimatorAux, 0, ty * tiles_x_ + tx));
        trace_camera_path(scene_, std::min(cx, width_ - 0.5), std::min(cy, height_ - 0.5), unused,
                          1, cache_paths_[ty * tiles_x_ + tx], ignored);
      }
    }
  }

  void build_tile_distributions(Iteration& it, TraceCounters& counters) {
    const std::size_t tiles = cache_paths_.size();
    const std::uint32_t n = static_cast<std::uint32_t>(it.vertices.size());
    it.tile_pmf.assign(tiles, {});
    it.tile_sampler.assign(tiles, {});
    it.tile_has_draws.assign(tiles, 0);
    if (n == 0) return;
    const bool visible_only = config_.flaw == SceneFlaw::kVisibleOnlyImportance;
    const bool visibility = visible_only || config_.cache_visibility;
    const ResamplingStep step(StepConfig{.M = n,
                                         .K = config_.draws,
                                         .selection = Selection::kImportance,
                                         .scheme = DrawScheme::kIndependent,
                                         .uniform_mix = visible_only ? 0.0 : config_.uniform_mix,
                                         .sampler = DiscreteSamplerKind::kAlias});
    std::vector<TraceCounters> tile_counters(tiles);
    tbb::parallel_for(std::size_t{0}, tiles, [&](std::size_t tile) {
      std::vector<double> importance(n, 0.0);
      const Subpath& cache = cache_paths_[tile];
      if (cache.size() == 2) {
        const ConnectOptions options{.visibility = visibility, .weighted = false};
        for (std::uint32_t i = 0; i < n; ++i) {
          const LightVertexRef& v = it.vertices[i];
          importance[i] = connect(scene_, std::span(it.pool[v.path]).first(v.count), cache, counts_,
                                  options, tile_counters[tile])
                              .max_channel();
        }
      }
      double total = 0.0;
      for (double w : importance) total += w;
      // With no mixing and nothing visible there is nothing to draw from (the control's bias).
      if (visible_only && total == 0.0) return;
      step.build_pmf(PoolView{.importance = importance}, it.tile_pmf[tile]);
      it.tile_sampler[tile].build(it.tile_pmf[tile], DiscreteSamplerKind::kAlias);
      it.tile_has_draws[tile] = 1;
    });
    for (const TraceCounters& c : tile_counters) counters.add(c);
  }

  const Scene& scene_;
  const RenderConfig& config_;
  std::uint64_t key_;
  std::uint32_t replicate_;
  StrategyCounts counts_;
  std::uint32_t width_, height_, max_length_;
  std::uint32_t tiles_x_, tiles_y_;
  std::vector<Subpath> cache_paths_;
  StrategyTally* strategies_;
};

}  // namespace

bool samples_all_paths(Method method, const Scene& scene) {
  if (method == Method::kPathTracing) {
    return !(scene.traits().has_point_lights && scene.traits().has_specular);
  }
  if (method == Method::kLightTracing) return !scene.traits().has_specular;
  return true;
}

StrategyCounts strategy_counts(const RenderConfig& config, const Scene& scene) {
  const double pool = pool_size(config, scene);
  switch (config.method) {
    case Method::kPathTracing:
      return {.emitter_hit = 1.0, .next_event = 1.0, .connection = 0.0, .light_tracing = 0.0};
    case Method::kLightTracing:
      return {.emitter_hit = 0.0, .next_event = 0.0, .connection = 0.0, .light_tracing = pool};
    case Method::kBdpt:
      return {.emitter_hit = 1.0, .next_event = 1.0, .connection = 1.0, .light_tracing = pool};
    case Method::kVertexConnection:
      return {.emitter_hit = 1.0, .next_event = pool, .connection = pool, .light_tracing = pool};
    case Method::kLightVertexCache:
    case Method::kProbabilistic: {
      const double k = config.draws;
      return {.emitter_hit = 1.0, .next_event = k, .connection = k, .light_tracing = pool};
    }
  }
  return {};
}

ReplicateImage render_replicate(const Scene& scene, const RenderConfig& config, std::uint64_t key,
                                std::uint32_t replicate, std::uint32_t iterations,
                                const std::atomic<bool>* interrupted, bool strategy_images) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  ReplicateImage out;
  out.image = Image(scene.description().width, scene.description().height);
  std::optional<StrategyTally> strategies;
  if (strategy_images) {
    strategies.emplace(strategy_counts(config, scene), scene.description().max_length,
                       scene.description().width, scene.description().height);
  }
  Renderer renderer(scene, config, key, replicate, strategies ? &*strategies : nullptr);
  for (std::uint32_t i = 0; i < iterations; ++i) {
    if (interrupted && interrupted->load()) break;
    renderer.iterate(i, out.image, out.counters);
  }
  for (double& v : out.image.values) v /= iterations;
  if (strategies) out.strategies = std::move(*strategies).per_iteration_mean(iterations);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.cpu_seconds = process_cpu_seconds() - cpu_start;
  return out;
}

}  // namespace pcbench::scene

#include "estimators/scene/render_replicate.h"

#include <chrono>
#include <ctime>

#include "integrands/scenes/render_services.h"
#include "integrands/scenes/strategy_tally.h"

namespace pcbench::scene {
namespace {

double process_cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

// `pool`: the iteration's light subpaths, in storage kept from the last iteration.
void iterate(const SceneEstimator& estimator, const RenderServices& services, ScenePass& pass,
             std::uint32_t index, LightPool& pool, Image& sum, TraceCounters& counters) {
  const Scene& scene = services.scene();
  services.trace_pool(index, estimator.pool_size(scene), pool, counters);
  pass.prepare(pool, counters);
  if (estimator.splats_to_camera(scene)) services.splat(pool, sum, counters);
  if (!estimator.traces_camera_paths(scene)) return;
  const bool emitter_hits = estimator.adds_emitter_hits(scene);
  if (pass.queues_connections()) {
    services.camera_pass_queued(index, sum, counters, emitter_hits,
                                [&](CameraPrefix& prefix, ConnectionQueue& queue) {
                                  pass.queue_connections(pool, prefix, queue);
                                });
  } else {
    services.camera_pass(index, sum, counters, [&](CameraPrefix& prefix, Rgb& value) {
      if (emitter_hits) value += services.connect_recorded({}, prefix);
      if (prefix.max_s > 0) value += pass.connections(pool, prefix);
    });
  }
  pass.finish_iteration(index, sum, counters);
}

}  // namespace

ReplicateImage render_replicate(const Scene& scene, const SceneEstimator& estimator,
                                std::uint64_t key, std::uint32_t replicate,
                                std::uint32_t iterations, const std::atomic<bool>* interrupted,
                                bool strategy_images) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  ReplicateImage out;
  out.image = Image(scene.description().width, scene.description().height);
  const StrategyCounts counts = estimator.strategy_counts(scene);
  std::optional<StrategyTally> strategies;
  if (strategy_images) {
    strategies.emplace(counts, scene.description().max_length, scene.description().width,
                       scene.description().height);
  }
  RenderServices services(scene, counts, key, replicate, strategies ? &*strategies : nullptr);
  const std::unique_ptr<ScenePass> pass = estimator.begin_replicate(services);
  services.use_count_model(pass->count_model());
  LightPool pool;
  for (std::uint32_t i = 0; i < iterations; ++i) {
    if (interrupted && interrupted->load()) break;
    iterate(estimator, services, *pass, i, pool, out.image, out.counters);
  }
  for (double& v : out.image.values) v /= iterations;
  if (strategies) out.strategies = std::move(*strategies).per_iteration_mean(iterations);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.cpu_seconds = process_cpu_seconds() - cpu_start;
  return out;
}

}  // namespace pcbench::scene

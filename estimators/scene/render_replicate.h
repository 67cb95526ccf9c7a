// Rendering one replicate of a scene with one scene estimator (scene_estimator.h): the
// iteration loop, the one place that asks an estimator what to do. Per iteration (one sample per
// pixel):
//   1. trace the estimator's pool of light subpaths (pool_size, possibly none);
//   2. let its pass prepare from the pool (guided estimators build their distributions);
//   3. splat the pool to the camera (t = 1) if it samples light tracing;
//   4. trace every pixel's camera subpath, if it samples any strategy with t >= 2, and for each
//      prefix y_0 .. y_{t-1} add the prefix's emitter hit (s = 0) if it samples those, then the
//      pass's connections;
//   5. let the pass finish the iteration with what needs other pixels (restir's reuse).
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>

#include "estimators/scene/scene_estimator.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"
#include "results/image.h"
#include "results/strategy_images.h"

namespace pcbench::scene {

struct ReplicateImage {
  Image image;  // per-pixel mean over the iterations
  TraceCounters counters;
  double seconds = 0.0;      // wall
  double cpu_seconds = 0.0;  // process CPU over the replicate (all threads)
  // With `strategy_images`: the image split by strategy (s, t), one replicate's worth
  // (integrands/scenes/strategy_tally.h).
  std::optional<StrategyImages> strategies = {};
};

// One replicate: `iterations` samples per pixel. Its random numbers come from (key, replicate)
// only, so the image is the same for any number of threads, with or without `strategy_images`
// (which costs a buffer per strategy, so it is off unless asked for).
ReplicateImage render_replicate(const Scene& scene, const SceneEstimator& estimator,
                                std::uint64_t key, std::uint32_t replicate,
                                std::uint32_t iterations,
                                const std::atomic<bool>* interrupted = nullptr,
                                bool strategy_images = false);

}  // namespace pcbench::scene

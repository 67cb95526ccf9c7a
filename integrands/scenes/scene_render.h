// Rendering one replicate of a scene with one member of the estimator family.
//
// An iteration takes one camera subpath per pixel and one pool of light subpaths shared by all
// pixels (DESIGN.md). What the methods do with the pool:
//   path tracing      no pool; next-event estimation samples an emitter vertex per camera vertex
//   light tracing     W·H light paths, each splatted to the camera (t = 1 only)
//   bdpt              W·H light paths; pixel i connects to light path i only
//   vertex connection M light paths; every camera vertex connects to every light vertex
//   light vertex cache M light paths; K light vertices drawn uniformly per camera vertex,
//                     weighted by N_v / (K M) (vertices drawn, paths counted)
//   probabilistic     M light paths; K light vertices drawn per first camera vertex from P ∝
//                     the unoccluded connection value at the pixel tile's cache point, mixed
//                     with uniform, weighted 1 / (K M P); deeper camera vertices draw uniformly
//                     (guide_all: every vertex from the tile's P)
// Every method except path tracing also splats its pool to the camera (t = 1), and every method
// except light tracing adds what its camera subpaths find on emitters (s = 0). The resampled
// methods draw with the same step as the analytic estimators (estimators/resampling_step.h).
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "harness/rng.h"
#include "integrands/scenes/connection.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"
#include "results/image.h"
#include "results/strategy_images.h"

namespace pcbench::scene {

enum class Method {
  kPathTracing,
  kLightTracing,
  kBdpt,
  kVertexConnection,
  kLightVertexCache,
  kProbabilistic
};

// Deliberate mistakes of the scene negative controls.
enum class SceneFlaw {
  kNone,
  // Probabilistic connections whose importance includes visibility at the tile's cache point,
  // with no uniform mixing: P = 0 for light vertices the cache point cannot see, although other
  // pixels of the tile can.
  kVisibleOnlyImportance,
  // The light vertex cache weighted 1 / K, normalised by vertices instead of by paths.
  kPerVertexNormalisation,
};

struct RenderConfig {
  Method method = Method::kBdpt;
  std::uint32_t light_paths = 0;  // M per iteration (W·H for bdpt and light tracing)
  std::uint32_t draws = 8;        // K per camera vertex (lvc, pcbpt)
  double uniform_mix = 0.1;       // pcbpt
  std::uint32_t tile = 8;         // pcbpt: pixels per side of a cache tile
  // pcbpt: guide every camera vertex by its tile's cache point, not just the first one (the
  // cache point is a first hit; deeper vertices are elsewhere and are drawn uniformly).
  bool guide_all = false;
  // pcbpt: the importance at the cache point includes its visibility to the light vertex (one
  // shadow ray per tile and light vertex). Light blocked at the cache point may still reach
  // other pixels of the tile, so this is unbiased only with uniform_mix > 0, which the
  // estimator's parameters require; without mixing it is the negative control below.
  bool cache_visibility = false;
  SceneFlaw flaw = SceneFlaw::kNone;
};

// Whether `method` samples every light-carrying path of `scene`: path tracing misses point light
// → mirror paths (no emitter to hit, no diffuse vertex to connect at); light tracing misses
// camera → mirror paths. Such an image is never a reference for the paths it cannot sample.
bool samples_all_paths(Method method, const Scene& scene);

// The strategy counts the MIS weights of `config` use (connection.h).
StrategyCounts strategy_counts(const RenderConfig& config, const Scene& scene);

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
ReplicateImage render_replicate(const Scene& scene, const RenderConfig& config, std::uint64_t key,
                                std::uint32_t replicate, std::uint32_t iterations,
                                const std::atomic<bool>* interrupted = nullptr,
                                bool strategy_images = false);

}  // namespace pcbench::scene

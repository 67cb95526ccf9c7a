// What the renderer offers a scene estimator (estimators/scene/scene_estimator.h), and nothing
// else: tracing an iteration's pool of light subpaths and every pixel's camera subpath with the
// replicate's random streams, connecting a light prefix with a camera prefix under the MIS
// weights of the estimator's strategy counts, splatting light tracing (t = 1) to the image,
// tallying the strategy images and counting the work. It knows no estimator: the loop that asks
// an estimator what to do with these is estimators/scene/render_replicate.h.
//
// Determinism: every random number comes from a stream of (key, replicate, purpose, iteration,
// path or pixel) (base/rng.h), and everything done in parallel (pool chunks, image rows) is
// summed in a fixed order, so an image does not depend on the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "base/rng.h"
#include "integrands/scenes/connection.h"
#include "integrands/scenes/connection_queue.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"
#include "results/image.h"

namespace pcbench::scene {

class StrategyTally;

using Subpath = std::vector<PathVertex>;

// One iteration's light subpaths x_0 .. x_{n-1}, shared by every pixel.
struct LightPool {
  std::vector<Subpath> paths;
};

// A light vertex of a pool, as the light prefix it ends: x_0 .. x_{count-1} of `path`.
struct LightVertexRef {
  std::uint32_t path = 0;
  std::uint32_t count = 0;  // s
};

// Every vertex of `pool`, path by path and along each path (what a light vertex cache draws).
std::vector<LightVertexRef> light_vertices(const LightPool& pool);

// The light prefix a vertex ends.
inline std::span<const PathVertex> light_prefix(const LightPool& pool, const LightVertexRef& v) {
  return std::span<const PathVertex>(pool.paths[v.path]).first(v.count);
}

// A camera prefix y_0 .. y_{t-1} (t >= 2) of one pixel's subpath, with what its connections use.
struct CameraPrefix {
  std::uint32_t pixel = 0;               // y · width + x
  std::span<const PathVertex> vertices;  // y_0 .. y_{t-1}
  // The most light vertices a connection may add within max_length (s + t - 1 <= max_length);
  // 0 when the prefix is already as long as a path may be.
  std::uint32_t max_s = 0;
  RandomStream& camera;     // the pixel's camera stream, where tracing its subpath left it
  RandomStream& draws;      // the pixel's resampling stream (StreamPurpose::kResampling)
  TraceCounters& counters;  // its row's

  std::uint32_t t() const { return static_cast<std::uint32_t>(vertices.size()); }
};

class RenderServices {
 public:
  // `strategies` (may be null) receives every recorded contribution again, by strategy.
  RenderServices(const Scene& scene, const StrategyCounts& counts, std::uint64_t key,
                 std::uint32_t replicate, StrategyTally* strategies);
  ~RenderServices();

  const Scene& scene() const { return scene_; }
  const StrategyCounts& counts() const { return counts_; }
  // Path-dependent counts for the next-event and connection strategies (connection.h): every
  // weight computed afterwards asks `model`, which must outlive the services' use.
  void use_count_model(const ConnectionCountModel* model) { counts_.model = model; }
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  std::uint32_t max_length() const { return max_length_; }
  // The replicate's stream for `purpose` (iteration or other index `sample`, path or pixel).
  StreamId stream(StreamPurpose purpose, std::uint32_t sample, std::uint32_t path) const;

  // `m` light subpaths for iteration `index`, path j from stream (kLightPool, index, j), into
  // `pool`, whose paths' storage from the last iteration is reused: allocating and freeing
  // every path each iteration let glibc return the heap to the system and fault it in again,
  // which had cost BDPT at 128×128 about 40% of its time (docs/findings/lanes.md).
  void trace_pool(std::uint32_t index, std::uint32_t m, LightPool& pool,
                  TraceCounters& counters) const;

  // Light tracing: every prefix of every pool path connected to the camera (t = 1), weighted
  // 1 / (pool size), added to `sum` and recorded as strategy (s, 1). One call at a time: the
  // chunks' splats are kept in storage the calls share.
  void splat(const LightPool& pool, Image& sum, TraceCounters& counters) const;

  // For every pixel (rows in parallel): traces its camera subpath of iteration `index` from
  // stream (kCameraPath, index, pixel), calls `each` on its prefixes t = 2, 3, … in order with
  // the pixel's running value, and adds the value to `sum`. `each` runs on several threads at
  // once, one row each.
  using PrefixVisitor = std::function<void(CameraPrefix& prefix, Rgb& value)>;
  void camera_pass(std::uint32_t index, Image& sum, TraceCounters& counters,
                   const PrefixVisitor& each) const;
  // The same with the connections deferred (connection_queue.h): `each` queues the connections
  // of each prefix; a row's queue is resolved with its shadow rays in packets, then every pixel
  // adds, prefix by prefix, its emitter hit (when `emitter_hits`: strategy (0, t), recorded)
  // and the sum of its connections (each recorded whole): the numbers camera_pass adds when
  // `each` adds the emitter hit and then the connections one by one.
  using QueueingVisitor = std::function<void(CameraPrefix& prefix, ConnectionQueue& queue)>;
  void camera_pass_queued(std::uint32_t index, Image& sum, TraceCounters& counters,
                          bool emitter_hits, const QueueingVisitor& each) const;

  // Strategy (light.size(), prefix.t()) with its MIS weight (connect() in connection.h); light
  // empty: the prefix's own emitter hit (s = 0). Counted in prefix.counters.
  Rgb connect(std::span<const PathVertex> light, const CameraPrefix& prefix) const;
  // The same for any camera prefix, with options (an unweighted or unoccluded value, such as
  // an importance).
  Rgb connect(std::span<const PathVertex> light, std::span<const PathVertex> camera,
              const ConnectOptions& options, TraceCounters& counters) const;
  // The strategy images' share of a contribution the estimator adds to the pixel (nothing
  // without --strategy-images).
  void record(std::uint32_t s, const CameraPrefix& prefix, const Rgb& value) const;
  // The same for a contribution added to pixel `pixel` after its camera pass (strategy (s, t)).
  void record(std::uint32_t s, std::uint32_t t, std::uint32_t pixel, const Rgb& value) const;
  // connect(), recorded whole: for estimators that add each connection as it is.
  Rgb connect_recorded(std::span<const PathVertex> light, const CameraPrefix& prefix) const;

 private:
  struct CameraRow;  // a row's camera subpaths and their streams (render_services.cpp)
  // Each thread's rows, light lanes and splat batches, and splat()'s chunks of splats, kept from
  // one iteration to the next.
  struct Scratch;
  // Walks row y's camera subpaths of iteration `index` in lanes.
  void walk_camera_row(std::uint32_t index, std::uint32_t y, CameraRow& row,
                       TraceCounters& counters) const;

  const Scene& scene_;
  StrategyCounts counts_;
  std::uint64_t key_;
  std::uint32_t replicate_;
  std::uint32_t width_, height_, max_length_;
  StrategyTally* strategies_;
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace pcbench::scene

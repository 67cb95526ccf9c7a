// Connections asked for now and traced later, many at a time: the deferred form of a scene
// estimator's connections (ScenePass::queue_connections, estimators/scene/scene_estimator.h).
//
// The renderer walks a row's camera subpaths in lanes, then lets the estimator queue the
// connections of each prefix, pixel by pixel. Resolving the queue computes every connection's
// unweighted, unoccluded value (connect() in connection.h without visibility or weight), traces
// the shadow rays of those that are not black as Embree packets (Scene::occluded_many), and
// weights the unblocked ones (mis_weight): the same value, counters and weight as connect()
// one by one, so a pixel sums the same numbers in the same order. A request is recorded whole
// in the strategy images, as RenderServices::connect_recorded records it.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "integrands/scenes/connection.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {

struct CameraPrefix;

// One connection of a batch: strategy (light.size(), camera.size()).
struct ConnectionPair {
  std::span<const PathVertex> light, camera;
};

// Connections computed many at a time: connect_all gives each pair the value connect() gives it
// (connection.h: the same value, weight and counters), its shadow ray traced with the batch's
// others as Embree packets. It keeps its buffers from one batch to the next.
class ConnectionBatch {
 public:
  // values[i] for pairs[i]; for a pair with t = 1 (light tracing), pixels[i] receives where it
  // lands, as connect()'s `pixel` does (`pixels` may be empty when no pair has t = 1).
  void connect_all(const Scene& scene, const StrategyCounts& counts,
                   std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                   TraceCounters& counters, std::span<std::optional<PixelPosition>> pixels = {});

 private:
  std::vector<double> weights_;  // next_event_batch.h's, when it computed the values
  std::vector<Scene::ShadowRay> shadows_;
  std::vector<std::uint32_t> shadowed_;  // the pair each shadow ray decides
  std::vector<std::uint8_t> blocked_;
};

class ConnectionQueue {
 public:
  // Strategy (light.size(), prefix.t()), its weighted value times `scale` (an estimator's
  // share of several samples). `light` must stay where it is until the row is resolved: a prefix
  // of a pool path.
  void connect(std::span<const PathVertex> light, const CameraPrefix& prefix, double scale = 1.0);
  // Strategy (1, prefix.t()) to a light vertex the pass sampled itself (next-event
  // estimation's emitter vertex): the queue keeps a copy.
  void connect(const PathVertex& light_vertex, const CameraPrefix& prefix, double scale = 1.0);

  // For the renderer (render_services.cpp) ------------------------------------------------
  // Empties the queue for a new row.
  void clear();
  // Starts the requests of `prefix` (its vertices must stay where they are until the row is
  // resolved), whose own emitter hit (s = 0) adds `emitter_hit` first when `adds_emitter_hit`.
  void begin_prefix(const CameraPrefix& prefix, bool adds_emitter_hit, const Rgb& emitter_hit);
  // Computes every request's weighted value, the shadow rays in packets; counts the work in
  // `counters`.
  void resolve(const Scene& scene, const StrategyCounts& counts, TraceCounters& counters);

  // A prefix with its requests: what it adds to its pixel, in the order the one-by-one loop
  // added it (its emitter hit, then the sum of its connections when it may connect).
  struct Prefix {
    std::span<const PathVertex> camera;
    std::uint32_t pixel = 0;
    bool adds_emitter_hit = false, connects = false;
    Rgb emitter_hit;
    std::uint32_t first = 0, end = 0;  // its requests
  };
  std::span<const Prefix> prefixes() const { return prefixes_; }
  // Request i's strategy s and weighted value (after resolve).
  std::uint32_t strategy(std::uint32_t i) const { return requests_[i].s; }
  const Rgb& value(std::uint32_t i) const { return values_[i]; }

 private:
  struct Request {
    const PathVertex* light = nullptr;  // null: owned_[owned]
    std::uint32_t s = 0;
    std::uint32_t owned = 0;
    double scale = 1.0;
  };
  std::span<const PathVertex> light_of(const Request& r) const {
    return {r.light != nullptr ? r.light : &owned_[r.owned], r.s};
  }

  std::vector<Prefix> prefixes_;
  std::vector<Request> requests_;
  std::vector<PathVertex> owned_;
  std::vector<ConnectionPair> pairs_;
  std::vector<Rgb> values_;
  ConnectionBatch batch_;
};

}  // namespace pcbench::scene

// Connections asked for now and traced later, many at a time: the deferred form of a scene
// estimator's connections (ScenePass::queue_connections, estimators/scene/scene_estimator.h).
//
// The renderer walks a row's camera subpaths in lanes, then lets the estimator queue the
// connections of each prefix, pixel by pixel. Resolving the queue computes every connection's
// unweighted, unoccluded value (connect() in connection.h without visibility or weight), traces
// the shadow rays of those that are not black as Embree packets (Scene::occluded_many), and
// weights the unblocked ones together (mis_weight's, connection_lanes.h): the same value,
// counters and weight as connect()
// one by one, so a pixel sums the same numbers in the same order. A request is recorded whole
// in the strategy images, as RenderServices::connect_recorded records it.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "base/rng.h"
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
  // For connections whose unoccluded values come with their weights (connection_lanes.h): the
  // shadow rays of the values that are not 0, light_ends[i] to camera_ends[i], as packets; each
  // unblocked value times weights[i], each blocked one 0, counted as connect_all counts.
  void trace_and_weigh(const Scene& scene, std::span<const Vec3> light_ends,
                       std::span<const Vec3> camera_ends, std::span<const double> weights,
                       std::span<Rgb> values, TraceCounters& counters);

 private:
  // The shadow rays and weights of connect_all and trace_and_weigh: value(i) sets values[i] if
  // it is not set yet, ends(i) gives connection i's two positions, weigh(which, weights) the MIS
  // weights of the connections `which` lists together (those whose values are not 0 and whose
  // shadow rays are not blocked), weights[k] for which[k].
  template <class Value, class Ends, class Weigh>
  void trace_and_weigh_each(const Scene& scene, const Value& value, const Ends& ends,
                            const Weigh& weigh, std::span<Rgb> values, TraceCounters& counters);

  std::vector<double> weights_;  // connection_lanes.h's, when it computed the values
  std::vector<Scene::ShadowRay> shadows_;
  std::vector<std::uint32_t> shadowed_;  // the pair each shadow ray decides
  std::vector<std::uint8_t> blocked_;
  std::vector<std::uint32_t> unblocked_;  // the connections to weigh
  std::vector<double> unblocked_weights_;
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
  // connect(sample_emitter_vertex(scene, rng), prefix, scale), the vertex's three uniforms drawn
  // from `rng` now and its point made when the row is resolved, with the row's others: under
  // counts with no strategy but emitter hits and next events, the points are drawn in lanes
  // (Emitters::sample_many) and connected without becoming vertices (connection_lanes.h).
  void connect_emitter_sample(RandomStream& rng, const CameraPrefix& prefix, double scale = 1.0);
  // The requests `prefix` queues after this call add up on their own first, and their sum joins
  // the ones before it: the prefix adds a + (b_1 + b_2 + …), as an estimator whose immediate form
  // added a group's sum to what it had (pcbpt's next event, then its draws' total) added it. At
  // most once per prefix.
  void begin_subtotal(const CameraPrefix& prefix);

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
    bool has_subtotal = false;
    std::uint32_t subtotal = 0;  // with has_subtotal: the first request of begin_subtotal's group
  };
  std::span<const Prefix> prefixes() const { return prefixes_; }
  // Request i's strategy s and weighted value (after resolve).
  std::uint32_t strategy(std::uint32_t i) const { return requests_[i].s; }
  const Rgb& value(std::uint32_t i) const { return values_[i]; }
  // What prefix p's requests add (after resolve): their values summed in order, begin_subtotal's
  // group on its own first.
  Rgb sum(const Prefix& p) const;

 private:
  struct Request {
    const PathVertex* light = nullptr;  // null: owned_[owned], or a sampled emitter vertex
    std::uint32_t s = 0;
    std::uint32_t owned = 0;  // a sampled one's: its uniforms at emitter_uniforms_[3 owned]
    double scale = 1.0;
    bool sampled = false;  // connect_emitter_sample's, its vertex not made yet
  };
  // The sampled requests' emitter vertices into owned_, for the one-by-one connections.
  void make_sampled_vertices(const Scene& scene);
  // Every request a sampled next event, under next_event_only counts: in lanes.
  void resolve_sampled_next_events(const Scene& scene, const StrategyCounts& counts,
                                   TraceCounters& counters);
  std::span<const PathVertex> light_of(const Request& r) const {
    return {r.light != nullptr ? r.light : &owned_[r.owned], r.s};
  }

  std::vector<Prefix> prefixes_;
  std::vector<Request> requests_;
  std::vector<PathVertex> owned_;
  std::vector<double> emitter_uniforms_;
  std::uint32_t sampled_ = 0;  // requests not made vertices yet
  std::vector<Vec3> light_ends_, camera_ends_;
  std::vector<const PathVertex*> camera_end_of_;
  std::vector<double> weights_;
  std::vector<ConnectionPair> pairs_;
  std::vector<Rgb> values_;
  ConnectionBatch batch_;
};

}  // namespace pcbench::scene

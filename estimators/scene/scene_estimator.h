// The scene estimator interface: the scene counterpart of Estimator (estimators/estimator.h).
//
// An iteration renders one sample per pixel: one pool of light subpaths shared by every pixel,
// one camera subpath per pixel (integrands/scenes/render_services.h traces both). A scene
// estimator says
//   - how many light subpaths an iteration needs (pool_size; 0 for none),
//   - how many samples per pixel and iteration it takes of each kind of strategy (s, t)
//     (strategy_counts): the counts of the balance heuristic, constants of the estimator and
//     the scene, never of the current pool, so that f stays independent of the pool. They also
//     say which strategies it samples at all: light tracing (t = 1, every pool path splatted to
//     the camera) when light_tracing > 0, the camera paths' own emitter hits (s = 0) when
//     emitter_hit > 0, connections (s, t >= 2) when next_event or connection > 0;
//   - which light-carrying paths it can sample at all (samples_all_paths; an image that misses
//     some is never a reference for them),
//   - and, through the ScenePass it makes per replicate: per-iteration preparation from the
//     pool (where a guided estimator builds its distributions), the connections of one
//     camera prefix (queued for the renderer to trace a row's shadow rays in packets, or
//     computed at once), and what needs other pixels' camera vertices (spatial reuse).
// The loop that runs it is estimators/scene/render_replicate.h; the renderer's services (tracing
// with the run's streams, connect() with its MIS weight, splats, strategy tallies, counters) are
// all an estimator uses. Each estimator is a file in estimators/scene/ named after its registry
// key; docs/dev/extending.md "Adding a scene estimator" walks through one.
#pragma once

#include <cstdint>
#include <memory>

#include "integrands/scenes/connection.h"
#include "integrands/scenes/connection_queue.h"
#include "integrands/scenes/render_services.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {

// One estimator at work on one replicate. prepare() runs once per iteration before any pixel,
// on the calling thread; connections() then runs for many pixels at once (one image row per
// thread), so it must leave the pass unchanged but for state of its own pixel (a slot per pixel,
// which only that pixel's thread writes); finish_iteration() runs after every pixel's
// connections, on the calling thread.
class ScenePass {
 public:
  virtual ~ScenePass() = default;

  // Per-iteration preparation from the iteration's pool, such as pcbpt's P tables. Work it
  // traces (shadow rays of an importance) is counted in `counters`.
  virtual void prepare(const LightPool& pool, TraceCounters& counters) {
    (void)pool;
    (void)counters;
  }

  // The connections of camera prefix y_0 .. y_{t-1} (t >= 2, prefix.max_s >= 1) with light
  // vertices, in one of two forms. A pass implements one of them.
  //
  // Queued (when queues_connections() is true): each connection asked of `queue`
  // (ConnectionQueue::connect, integrands/scenes/connection_queue.h) as it is found; the
  // renderer resolves a row's queue at once, its shadow rays in Embree packets, and adds and
  // records each connection whole. The fast form, for estimators whose every connection is its
  // weighted value times a factor known before it is made (pt, BDPT, lvc, pcbpt, ris's kept
  // sample).
  virtual bool queues_connections() const { return false; }
  virtual void queue_connections(const LightPool& pool, CameraPrefix& prefix,
                                 ConnectionQueue& queue) const {
    (void)pool;
    (void)prefix;
    (void)queue;
  }
  // Immediate: their sum, each MIS-weighted by RenderServices::connect (its shadow ray traced
  // there and then) and its share recorded by RenderServices::record (the strategy images must
  // add up to the image). The form of the estimators not moved to the queue, and of those that
  // use a connection's value or shadow ray before they add it (a visible target's kept sample).
  virtual Rgb connections(const LightPool& pool, CameraPrefix& prefix) const {
    (void)pool;
    (void)prefix;
    return {};
  }

  // Contributions of iteration `index` that need other pixels' camera vertices (restir's
  // spatial reuse, from the slots connections() left): added to `sum` (per-pixel sums of the
  // iteration, as camera_pass adds) and recorded by strategy, their work counted in `counters`.
  virtual void finish_iteration(std::uint32_t index, Image& sum, TraceCounters& counters) {
    (void)index;
    (void)sum;
    (void)counters;
  }

  // Path-dependent counts for the MIS weights of every strategy (ConnectionCountModel,
  // connection.h), or none: the estimator's constant StrategyCounts. prepare() may update the
  // model's state; connections() and the splats only read it.
  virtual const ConnectionCountModel* count_model() const { return nullptr; }
};

// Whether `scene` has paths only light subpaths can make: point light → mirror paths (no
// emitter for a camera subpath to hit, no diffuse vertex to connect at). Estimators without a
// pool (path tracing) miss them.
inline bool needs_light_subpaths(const Scene& scene) {
  return scene.traits().has_point_lights && scene.traits().has_specular;
}

class SceneEstimator {
 public:
  virtual ~SceneEstimator() = default;

  // Light subpaths per iteration, shared by every pixel (0: none).
  virtual std::uint32_t pool_size(const Scene& scene) const = 0;

  // Samples per pixel and iteration of each kind of strategy (connection.h), 0 for a kind it
  // does not sample.
  virtual StrategyCounts strategy_counts(const Scene& scene) const = 0;

  // Whether it samples every light-carrying path of `scene` (path tracing misses point light →
  // mirror paths; light tracing misses camera → mirror paths).
  virtual bool samples_all_paths(const Scene& scene) const {
    (void)scene;
    return true;
  }

  // The estimator's state for one replicate (pcbpt traces its cache points here); `services`
  // outlives the pass.
  virtual std::unique_ptr<ScenePass> begin_replicate(const RenderServices& services) const = 0;

  // What the counts say it samples (see the top of this file).
  bool splats_to_camera(const Scene& scene) const {
    return strategy_counts(scene).light_tracing > 0.0;
  }
  bool adds_emitter_hits(const Scene& scene) const {
    return strategy_counts(scene).emitter_hit > 0.0;
  }
  bool traces_camera_paths(const Scene& scene) const {
    const StrategyCounts c = strategy_counts(scene);
    return c.emitter_hit > 0.0 || c.next_event > 0.0 || c.connection > 0.0;
  }
};

}  // namespace pcbench::scene

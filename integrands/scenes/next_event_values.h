// The unweighted, unoccluded value of next-event strategy (1, t) at one camera prefix for many
// emitter points, as a resampling step weighs its candidates (estimators/scene/
// emitter_resampling.cpp): connect(scene, {x}, camera, counts, {.visibility = false, .weighted =
// false}) (connection.h) to the bit, counters included, without what connect computes for the
// weight and the shadow ray (both ends' densities, the ray's set-up) and without making x a
// PathVertex first. A candidate is then the emitter point, this value and the reservoir's step:
// through connect() the unused densities, the vertex and the ray set-up were about half of its
// cost, and one candidate at a time the rest waited on its divisions and square root
// (docs/findings/candidates.md). The points come in structure-of-arrays form (EmitterPoints)
// and are weighed in SIMD lanes. tests/next_event_values_test.cpp checks every value and
// counter against connect() on every built-in scene.
//
// The value is connect()'s expression term for term, in its order of operations:
//     x.beta · Le(x → y) · f_y(wo, y → x) · y.beta · (|cos_x| |cos_y| / d²),   x.beta = 1 / q(x),
// so that a reservoir weighs exactly what the one-by-one code weighed. The lanes keep that
// order and use no fused multiply-add (the vector code is built for AVX-512, AVX2 and SSE2 with
// contraction off: CMakeLists.txt), and IEEE division and square root are exact in any width:
// the same bits as scalar code.
#pragma once

#include <cstddef>
#include <span>

#include "integrands/scenes/connection.h"
#include "integrands/scenes/emitters.h"
#include "integrands/scenes/path_vertex.h"

namespace pcbench::scene {

// What one candidate's value needs beyond itself: the squared distance and distance of its
// segment, from which a visible target sets up its shadow ray as connect() does
// (Scene::shadow_ray). All zero where the value is.
struct NextEventValue {
  Rgb value;
  double distance_squared = 0.0;
  double distance = 0.0;
};

// NextEventValue for a batch of EmitterPoints, in structure-of-arrays form; no member is
// initialised (NextEventValues::values fills the first points.size).
struct NextEventValueLanes {
  static constexpr std::size_t kCapacity = EmitterPoints::kCapacity;
  double red[kCapacity], green[kCapacity], blue[kCapacity];
  double distance_squared[kCapacity], distance[kCapacity];

  NextEventValue operator[](std::size_t j) const {
    return {{red[j], green[j], blue[j]}, distance_squared[j], distance[j]};
  }
};

class NextEventValues {
 public:
  // `camera`: y_0 .. y_{t-1}, t >= 2.
  NextEventValues(const Scene& scene, std::span<const PathVertex> camera,
                  const StrategyCounts& counts);

  // The values at every point of `points`, into out[0 .. points.size).
  void values(const EmitterPoints& points, NextEventValueLanes& out, TraceCounters& counters) const;
  // One point's (restir's reuse weighs one candidate at a time).
  NextEventValue value(const EmitterPoint& x, TraceCounters& counters) const;

  const PathVertex& camera_end() const { return end_; }

 private:
  const PathVertex& end_;
  const Material& material_;
  bool connects_;
};

}  // namespace pcbench::scene

// A row's connections many at a time, in SIMD lanes: ConnectionBatch (connection_queue.h) hands
// a row's requests here instead of to connect() one at a time.
//
// Next events, value and weight together, for an estimator whose only strategies are emitter
// hits and next events (StrategyCounts without connections, light tracing or a count model:
// pt). One at a time they were about a third of path tracing's time: a PathVertex each side, the
// general weight's loops over the whole camera prefix (every term but one zero under these
// counts), and the segment, the emission and the camera end's BSDF computed twice, before the
// shadow ray and after it. Under these counts the balance heuristic of strategy (1, t) is
//     n_1 / (n_1 + n_0 · p_{0,t} / p_{1,t}),   p_{0,t} / p_{1,t} = p_y(y → x) |cos_x| / d² / p(x),
// which is what mis_weight's loops leave when every other term is zero (1 at a point light,
// which no path hits).
//
// Any other connection with s >= 1 (BDPT's, the light vertex cache's, pcbpt's draws, and light
// tracing's splats, t = 1), its value alone before the shadow ray; the weight needs both
// subpaths and is computed after it, for the connections that are not blocked only (on door-ajar
// nearly all are): connection_weights, in lanes where it can (t >= 2).
//
// The segments, emission and geometry terms, Lambertian ends' BSDFs and the next events' weights
// run in lanes across the connections (any other BSDF through bsdf_value, one at a time), in
// connect()'s order of operations, without fused multiply-adds (the file is built without
// contraction: CMakeLists.txt) and with IEEE's exact roots and quotients: the same values,
// weights and counters as connect() and mis_weight() to the bit
// (tests/connection_lanes_test.cpp; the images, ctest estimators.hashes).
#pragma once

#include <span>

#include "integrands/scenes/connection.h"
#include "integrands/scenes/connection_queue.h"
#include "integrands/scenes/emitters.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {

// Whether `counts` are an estimator's with no strategy but emitter hits and next events.
bool next_event_only(const StrategyCounts& counts);
// Whether every pair is a next-event connection: s = 1 from an emitter vertex, t >= 2.
bool all_next_events(std::span<const ConnectionPair> pairs);

// For next_event_only counts and all_next_events pairs: values[i], connect()'s unweighted,
// unoccluded value of pairs[i], and weights[i], its mis_weight() (for the pairs whose value is
// not 0), counting the work as connect() does.
void next_event_values_and_weights(const Scene& scene, const StrategyCounts& counts,
                                   std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                                   std::span<double> weights, TraceCounters& counters);
// The same for emitter points drawn together (Emitters::sample_many): point j connected to the
// camera end *camera_ends[j] (y_{t-1}, t >= 2) is the pair {emitter_vertex(points[j])} and that
// prefix, without making the vertex.
void next_event_values_and_weights(const Scene& scene, const StrategyCounts& counts,
                                   const EmitterPoints& points,
                                   std::span<const PathVertex* const> camera_ends,
                                   std::span<Rgb> values, std::span<double> weights,
                                   TraceCounters& counters);

// Whether every pair joins two vertices with a shadow ray on the camera side: s >= 1, t >= 2.
bool all_camera_surface_ends(std::span<const ConnectionPair> pairs);

// For all_camera_surface_ends pairs under any counts: values[i], connect()'s unweighted,
// unoccluded value of pairs[i], counting the work as connect() does. The segments, an emitter
// or Lambertian light end's f and a Lambertian camera end's run in the same lanes as the next
// events' (any other BSDF through bsdf_value, one at a time); the weight is connection_weights'.
void connection_values(const Scene& scene, const StrategyCounts& counts,
                       std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                       TraceCounters& counters);

// For pairs with s >= 1 and t >= 2 whose values are not 0 (the unblocked connections of a
// batch): weights[k], mis_weight() of pairs[which[k]] to the bit. In lanes where the weight comes
// from the subpaths' stored sums and the ends are Lambertian surfaces or an emitter
// (connection_weight_lanes.cpp), mis_weight() itself for any other pair.
void connection_weights(const Scene& scene, const StrategyCounts& counts,
                        std::span<const ConnectionPair> pairs, std::span<const std::uint32_t> which,
                        std::span<double> weights);

// Whether every pair is light tracing's: s >= 1 joined to the camera (t = 1).
bool all_light_tracing(std::span<const ConnectionPair> pairs);

// For all_light_tracing pairs under any counts: values[i], connect()'s unweighted, unoccluded
// value of pairs[i], and pixels[i] where connect() sets its `pixel` (left as it was where
// connect() returns first), counting the work as connect() does: the light ends' terms as
// connection_values computes them, the camera's projection and density in the same lanes.
void light_tracing_values(const Scene& scene, const StrategyCounts& counts,
                          std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                          std::span<std::optional<PixelPosition>> pixels, TraceCounters& counters);

}  // namespace pcbench::scene

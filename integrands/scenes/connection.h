// Connecting a light subpath prefix of s vertices with a camera subpath prefix of t vertices,
// with its multiple-importance-sampling weight.
//
// Strategy (s, t): s = 0 is a camera subpath that hits an emitter; t = 1 is light tracing (the
// light vertex connects to the camera and lands in some pixel); the others join x_{s-1} and
// y_{t-1} with a shadow ray. The weight is the balance heuristic over every strategy that could
// have made the same path, each counted with the number of samples the estimator takes of it per
// pixel and iteration (StrategyCounts). Those counts are constants of the estimator, or functions
// of the path (ConnectionCountModel), never properties of the current pool, so the weighted f
// stays independent of the pool (docs/guide/scenes.md, "MIS weights").
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "integrands/scenes/path_vertex.h"

namespace pcbench::scene {

// The count of a connection strategy (s >= 1, t >= 2) that depends on the path: an estimator
// that resamples its connections by importance (pcbpt's mis=resampling,
// estimators/scene/pcbpt.cpp) takes more effective samples of an important light vertex than of
// a dim one. The MIS weight asks it for every connection strategy that could make the path, so
// the weights still sum to 1; it must be a function of the path and of state fixed before the
// iteration's pool was traced (never of the current pool), so that the weighted f stays
// independent of the pool.
class ConnectionCountModel {
 public:
  virtual ~ConnectionCountModel() = default;
  // `importance`: the light side's contribution towards the camera-side end z_i without z_i's
  // BSDF, q* = max channel of Le · Π f · Π G / Π p_light over z_0 .. z_{i-1} and the segment to
  // z_i (the throughput × f × G a cache point's P uses); negative when the light side has a
  // specular vertex. `constant`: the StrategyCounts count of the strategy.
  virtual double count(double importance, const Vec3& camera_end, double constant) const = 0;
  // Whether next-event strategies (s = 1) are drawn as the connections are, and so asked too;
  // when not (pcbpt's nee=fresh), they keep their constant count.
  virtual bool counts_next_event() const { return true; }
};

// Samples per pixel and iteration of each kind of strategy; 0 where the estimator lacks it.
struct StrategyCounts {
  double emitter_hit = 1.0;    // s = 0
  double next_event = 1.0;     // s = 1, t >= 2
  double connection = 1.0;     // s >= 2, t >= 2
  double light_tracing = 0.0;  // t = 1: light paths per iteration (all splat to the image)
  // When set, the counts of next-event and connection strategies come from it (it must outlive
  // every weight computed with these counts).
  const ConnectionCountModel* model = nullptr;

  double count(std::uint32_t s, std::uint32_t t) const {
    if (t == 1) return light_tracing;
    if (s == 0) return emitter_hit;
    if (s == 1) return next_event;
    return connection;
  }
};

// The weight's sums over a subpath's own vertices (PathVertex::weight_sum), stored once the walk
// that made it is done, so that each of its connections' weights costs the same whatever the
// path's length instead of a loop over both subpaths (the recursive form of Georgiev et al.,
// "Implementing Vertex Connection and Merging", 2012). `counts` must be the counts every later
// weight of the subpath uses (the renderer's); under a count model (counts per path) nothing is
// stored and the weights loop, as they do for a subpath whose sums were never stored.
void store_camera_weight_sums(std::span<PathVertex> camera, const StrategyCounts& counts);
void store_light_weight_sums(std::span<PathVertex> light, const StrategyCounts& counts);

// Whether mis_weight() of strategy (s, t) takes the subpaths' stored sums (constant counts, and
// the sums stored where the weight reads them) rather than looping over both subpaths.
// Inline: connection_weights asks it of every connection it weighs.
inline bool weight_sums_stored(std::span<const PathVertex> light,
                               std::span<const PathVertex> camera, const StrategyCounts& counts) {
  const std::size_t s = light.size(), t = camera.size();
  return counts.model == nullptr && (t < 3 || !std::isnan(camera[t - 3].weight_sum)) &&
         (s < 3 || !std::isnan(light[s - 3].weight_sum));
}

// Balance-heuristic weight of strategy (s, t) for the path light[0..s) + camera[0..t) reversed.
double mis_weight(const Scene& scene, std::span<const PathVertex> light,
                  std::span<const PathVertex> camera, const StrategyCounts& counts);

struct ConnectOptions {
  bool visibility = true;  // false: the unoccluded value (importance), no shadow ray
  bool weighted = true;    // false: no MIS weight (importance, tests)
};

// The contribution of strategy (s, t) = (light.size(), camera.size()). For t = 1, `pixel`
// receives where it lands (nothing when it misses the image, and the result is 0).
Rgb connect(const Scene& scene, std::span<const PathVertex> light,
            std::span<const PathVertex> camera, const StrategyCounts& counts,
            const ConnectOptions& options, TraceCounters& counters,
            std::optional<PixelPosition>* pixel = nullptr);

}  // namespace pcbench::scene

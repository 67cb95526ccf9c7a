// The unweighted, unoccluded value of next-event strategy (1, t) at one camera prefix for many
// emitter points, as a resampling step weighs its candidates (estimators/scene/
// emitter_resampling.cpp): connect(scene, {x}, camera, counts, {.visibility = false, .weighted =
// false}) (connection.h) to the bit, counters included, without what connect computes for the
// weight and the shadow ray (both ends' densities, the ray's set-up) and without making x a
// PathVertex first. A candidate is then the emitter point, this value and the reservoir's step:
// through connect() the unused densities, the vertex and the ray set-up were about half of its
// cost (docs/findings/candidates.md). tests/next_event_values_test.cpp checks every value and
// counter against connect() on every built-in scene.
//
// The value is connect()'s expression term for term, in its order of operations:
//     x.beta · Le(x → y) · f_y(wo, y → x) · y.beta · (|cos_x| |cos_y| / d²),   x.beta = 1 / q(x),
// so that a reservoir weighs exactly what the one-by-one code weighed.
#pragma once

#include <cmath>
#include <span>

#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/connection.h"
#include "integrands/scenes/emitters.h"
#include "integrands/scenes/path_vertex.h"

namespace pcbench::scene {

// What one candidate's value needs beyond itself: the squared distance and distance of its
// segment, from which a visible target sets up its shadow ray as connect() does
// (Scene::shadow_ray).
struct NextEventValue {
  Rgb value;
  double distance_squared = 0.0;
  double distance = 0.0;
};

class NextEventValues {
 public:
  // `camera`: y_0 .. y_{t-1}, t >= 2.
  NextEventValues(const Scene& scene, std::span<const PathVertex> camera,
                  const StrategyCounts& counts)
      : end_(camera.back()),
        material_(scene.material(end_.triangle)),
        connects_(counts.count(1, static_cast<std::uint32_t>(camera.size())) > 0.0 && !end_.delta) {
  }

  NextEventValue value(const EmitterPoint& x, TraceCounters& counters) const {
    if (!connects_) return {};
    ++counters.connections;
    const Vec3 d = end_.position - x.position;
    const double distance_squared = dot(d, d);
    if (distance_squared == 0.0) return {};
    const double distance = std::sqrt(distance_squared);
    const double inv_distance = 1.0 / distance;
    const Vec3 w = d * inv_distance;  // from x towards the camera end
    const double inv_distance_squared = inv_distance * inv_distance;
    // emitted_towards, emission_pdf's neighbour abs_cos_at and the vertex's beta, on the point.
    const Rgb emitted = x.point_light || dot(x.normal, w) > 0.0 ? x.radiance : Rgb{};
    const double cos_x = x.point_light ? 1.0 : std::abs(dot(x.normal, w));
    const Rgb value = (Rgb{1.0, 1.0, 1.0} / x.pdf_area) * emitted *
                      bsdf_eval(material_, end_.normal, end_.to_previous, -w) * end_.beta *
                      (cos_x * std::abs(dot(end_.normal, w)) * inv_distance_squared);
    if (value.is_black()) {
      ++counters.skipped_zero;
      return {};
    }
    return {value, distance_squared, distance};
  }

  const PathVertex& camera_end() const { return end_; }

 private:
  const PathVertex& end_;
  const Material& material_;
  bool connects_;
};

}  // namespace pcbench::scene

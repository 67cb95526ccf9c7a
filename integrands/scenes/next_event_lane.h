// One SIMD lane of a next event x -> y (x an emitter point, y the camera end y_{t-1}): the
// arithmetic connect() does for strategy (1, t), written once for the two kernels that run it
// across lanes with different layouts: NextEventValues (next_event_values.cpp: one camera end,
// many points, a resampling step's candidates) and connection_lanes.cpp (a point per camera end,
// a row's next events). Each step is inline so that the kernel's loop, built without
// contraction and without errno (CMakeLists.txt), vectorises with it; the order of operations is
// connect()'s, so both kernels give its values to the bit.
#pragma once

#include <cmath>

#include "base/lane_select.h"
#include "integrands/scenes/scene_math.h"

namespace pcbench::scene::next_event_lane {

// The segment from x to y and the terms that depend on it alone.
struct Segment {
  Vec3 w;  // unit, from x to y
  double distance_squared, distance, inv_distance_squared;
  double cos_x;     // |cos| at x, 1 at a point light (emitted_towards, abs_cos_at)
  double geometry;  // cos_x |cos at y| / d²
  bool emits;       // x emits towards y: in front of the triangle, or a point light
};

[[gnu::always_inline]] inline Segment segment(const Vec3& x, const Vec3& x_normal, bool point_light,
                                              const Vec3& y, const Vec3& y_normal) {
  const Vec3 d = y - x;
  const double distance_squared = dot(d, d);
  const double distance = std::sqrt(distance_squared);
  const double inv_distance = 1.0 / distance;
  const Vec3 w = d * inv_distance;
  const double cos_at_x = dot(x_normal, w);
  const double cos_x = lane_select(point_light, 1.0, std::abs(cos_at_x));
  const double inv_distance_squared = inv_distance * inv_distance;
  return {.w = w,
          .distance_squared = distance_squared,
          .distance = distance,
          .inv_distance_squared = inv_distance_squared,
          .cos_x = cos_x,
          .geometry = cos_x * std::abs(dot(y_normal, w)) * inv_distance_squared,
          .emits = static_cast<bool>(point_light | (cos_at_x > 0.0))};
}

// The radiance x sends towards y: its own where it emits that way, else 0.
[[gnu::always_inline]] inline Rgb emitted(const Segment& s, const Rgb& radiance) {
  return {lane_select(s.emits, radiance.r, 0.0), lane_select(s.emits, radiance.g, 0.0),
          lane_select(s.emits, radiance.b, 0.0)};
}

// A Lambertian y's cosine towards wi = -w on the side of its facing normal (the normal turned to
// wo, bsdf_detail::facing): f and the density are nonzero only where this is > 0 and wo is in
// front too.
[[gnu::always_inline]] inline double lambertian_cos(const Vec3& facing, const Vec3& w) {
  return dot(facing, -w);
}

// connect()'s value ((x.beta · Le) · f) · y.beta · G, or 0 where it is black or the segment
// empty (`keep` false); `skipped_zero` when it is black with a segment of nonzero length (what
// connect() counts as skipped_zero).
struct Value {
  double r, g, b;
  bool keep, skipped_zero;
};

[[gnu::always_inline]] inline Value value(const Rgb& x_beta, const Rgb& emitted, const Rgb& f,
                                          const Rgb& y_beta, double geometry,
                                          double distance_squared) {
  const double r = x_beta.r * emitted.r * f.r * y_beta.r * geometry;
  const double g = x_beta.g * emitted.g * f.g * y_beta.g * geometry;
  const double b = x_beta.b * emitted.b * f.b * y_beta.b * geometry;
  const bool segment = distance_squared != 0.0;
  const bool black = (r == 0.0) & (g == 0.0) & (b == 0.0);
  const bool keep = segment & !black;
  const bool skipped_zero = segment & black;
  return {lane_select(keep, r, 0.0), lane_select(keep, g, 0.0), lane_select(keep, b, 0.0), keep,
          skipped_zero};
}

}  // namespace pcbench::scene::next_event_lane

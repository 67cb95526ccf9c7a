#include "integrands/scenes/next_event_values.h"

#include "base/lane_select.h"
#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/next_event_lane.h"

namespace pcbench::scene {

namespace next_event_lanes {

// What the lanes share: the camera end y = y_{t-1}.
struct CameraEnd {
  Vec3 position, normal, facing;  // facing: the normal turned to the side of wo (bsdf_eval's)
  Rgb beta;
  bool wo_in_front;  // bsdf_eval's first same-side test, which does not depend on wi
  const Material* material;
  const Vec3* wo;
};

// Three passes over the batch: (1) in lanes, the segment from x to y, its direction w and the
// geometry and emission terms; (2) f_y(wo, -w): a Lambertian end's in lanes, any other's
// through bsdf_eval one point at a time; (3) in lanes, the products in connect()'s order and
// the zero tests; each lane's arithmetic next_event_lane.h's, which connection_lanes.cpp's
// lanes share. Built three times, for SSE2, AVX2 and AVX-512 (8 doubles wide; no FMA in any:
// see the header), the widest the machine has chosen at run time.
// Returns how many values were zero with a segment of nonzero length (skipped_zero).
[[gnu::target_clones("avx512f", "avx2", "default")]] std::size_t weigh(const CameraEnd& y,
                                                                       const EmitterPoints& p,
                                                                       NextEventValueLanes& out) {
  constexpr std::size_t K = EmitterPoints::kCapacity;
  const std::size_t n = p.size;
  double wx[K], wy[K], wz[K], geometry[K], er[K], eg[K], eb[K], fr[K], fg[K], fb[K];
  for (std::size_t j = 0; j < n; ++j) {
    const next_event_lane::Segment s = next_event_lane::segment(
        {p.x[j], p.y[j], p.z[j]}, {p.normal_x[j], p.normal_y[j], p.normal_z[j]},
        p.point_light[j] != 0.0, y.position, y.normal);
    wx[j] = s.w.x;
    wy[j] = s.w.y;
    wz[j] = s.w.z;
    const Rgb e = next_event_lane::emitted(s, {p.red[j], p.green[j], p.blue[j]});
    er[j] = e.r;
    eg[j] = e.g;
    eb[j] = e.b;
    geometry[j] = s.geometry;
    out.distance_squared[j] = s.distance_squared;
    out.distance[j] = s.distance;
  }
  if (y.material->kind == MaterialKind::kDiffuse) {
    // bsdf_eval's same-side test: dot(n, wo) > 0 for all lanes, dot(n, wi) > 0 for wi = -w.
    const Rgb f = y.wo_in_front ? y.material->albedo * kInvPi : Rgb{};
    for (std::size_t j = 0; j < n; ++j) {
      const bool front = next_event_lane::lambertian_cos(y.facing, {wx[j], wy[j], wz[j]}) > 0.0;
      fr[j] = lane_select(front, f.r, 0.0);
      fg[j] = lane_select(front, f.g, 0.0);
      fb[j] = lane_select(front, f.b, 0.0);
    }
  } else {
    for (std::size_t j = 0; j < n; ++j) {
      const Rgb f = bsdf_eval(*y.material, y.normal, *y.wo, -Vec3{wx[j], wy[j], wz[j]});
      fr[j] = f.r;
      fg[j] = f.g;
      fb[j] = f.b;
    }
  }
  std::size_t skipped_zero = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const double inv_pdf = 1.0 / p.pdf_area[j];  // x's beta
    const next_event_lane::Value v =
        next_event_lane::value({inv_pdf, inv_pdf, inv_pdf}, {er[j], eg[j], eb[j]},
                               {fr[j], fg[j], fb[j]}, y.beta, geometry[j], out.distance_squared[j]);
    skipped_zero += static_cast<std::size_t>(v.skipped_zero);
    out.red[j] = v.r;
    out.green[j] = v.g;
    out.blue[j] = v.b;
    out.distance_squared[j] = lane_select(v.keep, out.distance_squared[j], 0.0);
    out.distance[j] = lane_select(v.keep, out.distance[j], 0.0);
  }
  return skipped_zero;
}

}  // namespace next_event_lanes

NextEventValues::NextEventValues(const Scene& scene, std::span<const PathVertex> camera,
                                 const StrategyCounts& counts)
    : end_(camera.back()),
      material_(scene.material(end_.triangle)),
      connects_(counts.count(1, static_cast<std::uint32_t>(camera.size())) > 0.0 && !end_.delta) {}

void NextEventValues::values(const EmitterPoints& points, NextEventValueLanes& out,
                             TraceCounters& counters) const {
  const std::size_t n = points.size;
  if (!connects_) {
    for (std::size_t j = 0; j < n; ++j) {
      out.red[j] = out.green[j] = out.blue[j] = 0.0;
      out.distance_squared[j] = out.distance[j] = 0.0;
    }
    return;
  }
  counters.connections += n;
  const Vec3 facing = bsdf_detail::facing(end_.normal, end_.to_previous);
  const next_event_lanes::CameraEnd y{.position = end_.position,
                                      .normal = end_.normal,
                                      .facing = facing,
                                      .beta = end_.beta,
                                      .wo_in_front = dot(facing, end_.to_previous) > 0.0,
                                      .material = &material_,
                                      .wo = &end_.to_previous};
  counters.skipped_zero += next_event_lanes::weigh(y, points, out);
}

NextEventValue NextEventValues::value(const EmitterPoint& x, TraceCounters& counters) const {
  EmitterPoints one;
  one.size = 1;
  one.set(0, x);
  NextEventValueLanes out;
  values(one, out, counters);
  return out[0];
}

}  // namespace pcbench::scene

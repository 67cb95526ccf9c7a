#include "integrands/scenes/connection_lanes.h"

#include <algorithm>

#include "base/lane_select.h"
#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/lane_vec3.h"
#include "integrands/scenes/next_event_lane.h"

namespace pcbench::scene {
namespace {

constexpr std::size_t kChunk = 64;  // connections a pass of the lanes takes

// A chunk's connections in structure-of-arrays form: x = x_{s-1} (the emitter vertex of a next
// event), y = y_{t-1}.
// A connection that connect() drops before its segment (a delta end) has all its inputs 0,
// which makes its segment empty and so its value 0, as it must be.
struct Chunk {
  std::size_t size = 0;
  // Gathered, one connection at a time.
  double x_x[kChunk], x_y[kChunk], x_z[kChunk];  // x's position
  // An emitter x's normal (0 at a point light); a surface x's turned to wo (bsdf_detail::facing).
  double xn_x[kChunk], xn_y[kChunk], xn_z[kChunk];
  double point_light[kChunk];  // 1 or 0
  double x_front[kChunk];      // 1 unless x is a surface whose wo lies behind its facing normal
  // x's radiance in front of it (or intensity); a Lambertian surface x's albedo / π.
  double le_r[kChunk], le_g[kChunk], le_b[kChunk];
  double xb_r[kChunk], xb_g[kChunk], xb_b[kChunk];  // x's beta, 1 / p(x)
  double x_pdf[kChunk];                             // p(x), x's pdf_fwd
  double y_x[kChunk], y_y[kChunk], y_z[kChunk];     // y's position
  double yn_x[kChunk], yn_y[kChunk], yn_z[kChunk];  // y's normal
  double yf_x[kChunk], yf_y[kChunk], yf_z[kChunk];  // y's normal turned to wo (bsdf_detail::facing)
  double wo_in_front[kChunk];  // 1 when dot(facing, wo) > 0: bsdf_value's first same-side test
  double yb_r[kChunk], yb_g[kChunk], yb_b[kChunk];  // y's beta
  double fd_r[kChunk], fd_g[kChunk], fd_b[kChunk];  // a Lambertian y's albedo / π
  // Computed in lanes (f and pdf_y by bsdf_value where y is not Lambertian).
  double w_x[kChunk], w_y[kChunk], w_z[kChunk];  // the segment's direction, x to y
  double distance_squared[kChunk], inv_distance_squared[kChunk];
  double cos_x[kChunk], geometry[kChunk];
  double f_r[kChunk], f_g[kChunk], f_b[kChunk];  // f_y(wo, -w)
  double pdf_y[kChunk];                          // of sampling -w at y given wo
  // Light tracing's (lens_values): the value, where -w meets the film, and 1 where it lands.
  double value_r[kChunk], value_g[kChunk], value_b[kChunk];
  double film_x[kChunk], film_y[kChunk], film_cos[kChunk], lands[kChunk];
};

// The segment, geometry terms, x's emission or Lambertian f (both "what x sends towards y, where
// it sends it": emitted_towards' side test, or bsdf_value's on the normal turned to wo), and a
// Lambertian y's f and density, as connect() computes them (segment_between, abs_cos_at,
// bsdf_value), each lane's arithmetic next_event_lane.h's, which NextEventValues' lanes share.
[[gnu::target_clones("avx512f", "avx2", "default")]] void segments_and_ends(Chunk& c) {
  for (std::size_t j = 0; j < c.size; ++j) {
    const next_event_lane::Segment s = next_event_lane::segment(
        {c.x_x[j], c.x_y[j], c.x_z[j]}, {c.xn_x[j], c.xn_y[j], c.xn_z[j]}, c.point_light[j] != 0.0,
        {c.y_x[j], c.y_y[j], c.y_z[j]}, {c.yn_x[j], c.yn_y[j], c.yn_z[j]});
    c.w_x[j] = s.w.x;
    c.w_y[j] = s.w.y;
    c.w_z[j] = s.w.z;
    c.distance_squared[j] = s.distance_squared;
    c.inv_distance_squared[j] = s.inv_distance_squared;
    next_event_lane::Segment gated = s;  // a surface x scatters only when wo is in front too
    gated.emits = gated.emits & (c.x_front[j] != 0.0);
    const Rgb le = next_event_lane::emitted(gated, {c.le_r[j], c.le_g[j], c.le_b[j]});
    c.le_r[j] = le.r;
    c.le_g[j] = le.g;
    c.le_b[j] = le.b;
    c.cos_x[j] = s.cos_x;
    c.geometry[j] = s.geometry;
    // f and the density of a Lambertian y towards wi = -w.
    const double n_wi = next_event_lane::lambertian_cos({c.yf_x[j], c.yf_y[j], c.yf_z[j]}, s.w);
    const bool same_side = (c.wo_in_front[j] != 0.0) & (n_wi > 0.0);
    c.f_r[j] = lane_select(same_side, c.fd_r[j], 0.0);
    c.f_g[j] = lane_select(same_side, c.fd_g[j], 0.0);
    c.f_b[j] = lane_select(same_side, c.fd_b[j], 0.0);
    c.pdf_y[j] = lane_select(same_side, n_wi * kInvPi, 0.0);
  }
}

// Lane j's value (next_event_lane::value) into red, green and blue[j]; whether it is 0 with a
// segment of nonzero length (connect()'s skipped_zero).
[[gnu::always_inline]] inline bool lane_value(const Chunk& c, std::size_t j, double* red,
                                              double* green, double* blue) {
  const next_event_lane::Value v =
      next_event_lane::value({c.xb_r[j], c.xb_g[j], c.xb_b[j]}, {c.le_r[j], c.le_g[j], c.le_b[j]},
                             {c.f_r[j], c.f_g[j], c.f_b[j]}, {c.yb_r[j], c.yb_g[j], c.yb_b[j]},
                             c.geometry[j], c.distance_squared[j]);
  red[j] = v.r;
  green[j] = v.g;
  blue[j] = v.b;
  return v.skipped_zero;
}

// connect()'s value and the weight n_1 / (n_1 + n_0 ratio), ratio = remap0(p_y |cos_x| / d²) /
// remap0(p(x)) as balance_weight forms it (0 at a point light). Returns the connections whose
// value is 0 with a segment of nonzero length (skipped_zero).
[[gnu::target_clones("avx512f", "avx2", "default")]] std::size_t values_and_weights(
    const Chunk& c, double next_event, double emitter_hit, double* red, double* green, double* blue,
    double* weights) {
  std::size_t skipped_zero = 0;
  for (std::size_t j = 0; j < c.size; ++j) {
    skipped_zero += static_cast<std::size_t>(lane_value(c, j, red, green, blue));
    const double light_end = c.pdf_y[j] * c.cos_x[j] * c.inv_distance_squared[j];
    const double ratio = lane_select(light_end != 0.0, light_end, 1.0) /
                         lane_select(c.x_pdf[j] != 0.0, c.x_pdf[j], 1.0);
    const double others = lane_select(c.point_light[j] != 0.0, 0.0, ratio * emitter_hit);
    weights[j] = next_event / (next_event + others);
  }
  return skipped_zero;
}

// connect()'s values alone (any strategy's weight is mis_weight's, after the shadow ray).
[[gnu::target_clones("avx512f", "avx2", "default")]] std::size_t values(const Chunk& c, double* red,
                                                                        double* green,
                                                                        double* blue) {
  std::size_t skipped_zero = 0;
  for (std::size_t j = 0; j < c.size; ++j) {
    skipped_zero += static_cast<std::size_t>(lane_value(c, j, red, green, blue));
  }
  return skipped_zero;
}

// Light tracing's values (t = 1, y the camera): connect()'s (x.beta · f_x) · (|cos_x| / d² ·
// p_lens), p_lens the pixel's density at the film point -w meets (0 off the film), into
// c.value_*; c.lands is 1 where connect() would return a pixel (a segment of nonzero length whose
// direction meets the film), c.film_* that pixel's film position and cosine. The results go to
// the chunk, not to separate arrays: GCC gives up on vectorising a loop that stores through that
// many pointers that might alias. Returns the connections that land with a value of 0
// (skipped_zero).
[[gnu::target_clones("avx512f", "avx2", "default")]] std::size_t lens_values(
    Chunk& c, const CameraModel& camera) {
  // A copy the stores below cannot alias, so that its members stay in registers.
  const CameraModel lens = camera;
  std::size_t skipped_zero = 0;
  for (std::size_t j = 0; j < c.size; ++j) {
    const CameraModel::FilmPoint p = lens.film_point(-Vec3{c.w_x[j], c.w_y[j], c.w_z[j]});
    const double pdf = lane_select(p.on_film, lens.pixel_pdf(p.cos_theta), 0.0);
    const double scale = c.cos_x[j] * c.inv_distance_squared[j] * pdf;
    const double r = c.xb_r[j] * c.le_r[j] * scale;
    const double g = c.xb_g[j] * c.le_g[j] * scale;
    const double b = c.xb_b[j] * c.le_b[j] * scale;
    const bool land = (c.distance_squared[j] != 0.0) & p.on_film;
    const bool black = (r == 0.0) & (g == 0.0) & (b == 0.0);
    const bool keep = land & !black;
    skipped_zero += static_cast<std::size_t>(land & black);
    c.value_r[j] = lane_select(keep, r, 0.0);
    c.value_g[j] = lane_select(keep, g, 0.0);
    c.value_b[j] = lane_select(keep, b, 0.0);
    c.film_x[j] = lane_select(land, p.fx, 0.0);
    c.film_y[j] = lane_select(land, p.fy, 0.0);
    c.film_cos[j] = p.cos_theta;
    c.lands[j] = lane_select(land, 1.0, 0.0);
  }
  return skipped_zero;
}

}  // namespace

bool next_event_only(const StrategyCounts& counts) {
  return counts.connection <= 0.0 && counts.light_tracing <= 0.0 && counts.model == nullptr;
}

bool all_next_events(std::span<const ConnectionPair> pairs) {
  return std::all_of(pairs.begin(), pairs.end(), [](const ConnectionPair& p) {
    return p.light.size() == 1 && p.light[0].kind == VertexKind::kEmitter && p.camera.size() >= 2;
  });
}

namespace {

// `v`, or for a lane that does not connect a vertex whose every member is 0.
const PathVertex& lane_vertex(const PathVertex& v, bool connects) {
  static const PathVertex none;
  return connects ? v : none;
}

// Lane j's x from an emitter vertex (a delta vertex or an unconnected lane: `connects` false,
// every input 0).
void gather_emitter_vertex(const Scene& scene, const PathVertex& x, bool connects, Chunk& c,
                           std::size_t j) {
  const PathVertex& v = lane_vertex(x, connects);
  put(c.x_x, c.x_y, c.x_z, j, v.position);
  put(c.xn_x, c.xn_y, c.xn_z, j, v.normal);
  c.point_light[j] = v.point_light ? 1.0 : 0.0;
  c.x_front[j] = 1.0;
  const Rgb le = !connects       ? Rgb{}
                 : x.point_light ? scene.description().point_lights[x.triangle].intensity
                                 : scene.triangle(x.triangle).emission;
  c.le_r[j] = le.r, c.le_g[j] = le.g, c.le_b[j] = le.b;
  c.xb_r[j] = v.beta.r, c.xb_g[j] = v.beta.g, c.xb_b[j] = v.beta.b;
  c.x_pdf[j] = v.pdf_fwd;
}

// Lane j's x from point i of a batch Emitters::sample_many drew: what emitter_vertex makes of it
// (beta 1 / p(x), pdf_fwd p(x); a point's radiance is its triangle's emission or its light's
// intensity), or every input 0 when the lane does not connect.
void gather_emitter_point(const EmitterPoints& points, std::size_t i, bool connects, Chunk& c,
                          std::size_t j) {
  const double on = connects ? 1.0 : 0.0;  // multiplies only finite inputs, so 0 or the input
  c.x_x[j] = on * points.x[i], c.x_y[j] = on * points.y[i], c.x_z[j] = on * points.z[i];
  c.xn_x[j] = on * points.normal_x[i], c.xn_y[j] = on * points.normal_y[i],
  c.xn_z[j] = on * points.normal_z[i];
  c.point_light[j] = on * points.point_light[i];
  c.x_front[j] = 1.0;
  c.le_r[j] = on * points.red[i], c.le_g[j] = on * points.green[i], c.le_b[j] = on * points.blue[i];
  const double beta = connects ? 1.0 / points.pdf_area[i] : 0.0;
  c.xb_r[j] = beta, c.xb_g[j] = beta, c.xb_b[j] = beta;
  c.x_pdf[j] = on * points.pdf_area[i];
}

// Lane j's y, y_{t-1} of `camera` (every input 0 when the lane does not connect); whether its
// BSDF is Lambertian (or the lane unconnected), which the lanes compute.
bool gather_camera_end(const Scene& scene, const PathVertex& y, bool connects, Chunk& c,
                       std::size_t j) {
  const PathVertex& v = lane_vertex(y, connects);
  put(c.y_x, c.y_y, c.y_z, j, v.position);
  put(c.yn_x, c.yn_y, c.yn_z, j, v.normal);
  const Vec3 facing = bsdf_detail::facing(v.normal, v.to_previous);
  put(c.yf_x, c.yf_y, c.yf_z, j, facing);
  c.wo_in_front[j] = dot(facing, v.to_previous) > 0.0 ? 1.0 : 0.0;
  c.yb_r[j] = v.beta.r, c.yb_g[j] = v.beta.g, c.yb_b[j] = v.beta.b;
  const Material& m = scene.material(v.triangle);
  const Rgb fd = m.albedo * kInvPi;
  c.fd_r[j] = fd.r, c.fd_g[j] = fd.g, c.fd_b[j] = fd.b;
  return !connects || m.kind == MaterialKind::kDiffuse;
}

// Lane j's x, the light end x_{s-1} of a connection with s >= 2 (every input 0 when the lane does
// not connect): a surface vertex, scattering towards the camera end; whether its BSDF is
// Lambertian (or the lane unconnected), which the lanes compute.
bool gather_surface_light_end(const Scene& scene, const PathVertex& x, bool connects, Chunk& c,
                              std::size_t j) {
  const PathVertex& v = lane_vertex(x, connects);
  put(c.x_x, c.x_y, c.x_z, j, v.position);
  // bsdf_value's normal turned to wo: its sign is the side test's, and |cos| is the same.
  const Vec3 facing = bsdf_detail::facing(v.normal, v.to_previous);
  put(c.xn_x, c.xn_y, c.xn_z, j, facing);
  c.point_light[j] = 0.0;
  c.x_front[j] = dot(facing, v.to_previous) > 0.0 ? 1.0 : 0.0;
  const Material& m = scene.material(v.triangle);
  const Rgb fd = m.albedo * kInvPi;
  c.le_r[j] = fd.r, c.le_g[j] = fd.g, c.le_b[j] = fd.b;
  c.xb_r[j] = v.beta.r, c.xb_g[j] = v.beta.g, c.xb_b[j] = v.beta.b;
  c.x_pdf[j] = v.pdf_fwd;
  return !connects || m.kind == MaterialKind::kDiffuse;
}

// Lane j's y for light tracing, the camera's vertex y_0: its position alone (no BSDF; the
// other members 0).
void gather_lens(const PathVertex& y, bool connects, Chunk& c, std::size_t j) {
  put(c.y_x, c.y_y, c.y_z, j, lane_vertex(y, connects).position);
  put(c.yn_x, c.yn_y, c.yn_z, j, {});
  put(c.yf_x, c.yf_y, c.yf_z, j, {});
  c.wo_in_front[j] = 0.0;
  c.yb_r[j] = c.yb_g[j] = c.yb_b[j] = 0.0;
  c.fd_r[j] = c.fd_g[j] = c.fd_b[j] = 0.0;
}

// Lane j's x, a connection's light end x_{s-1}: an emitter vertex or a surface; whether the
// lanes compute its f (an emitter, or a Lambertian surface, or an unconnected lane).
bool gather_light_end(const Scene& scene, const PathVertex& x, bool connects, Chunk& c,
                      std::size_t j) {
  if (x.kind == VertexKind::kEmitter) {
    gather_emitter_vertex(scene, x, connects, c, j);
    return true;
  }
  return gather_surface_light_end(scene, x, connects, c, j);
}

// Whether a pair connects at all under `counts` (connect()'s first tests): its strategy counted,
// neither end a delta vertex.
bool pair_connects(const StrategyCounts& counts, const ConnectionPair& pair) {
  const double count = counts.count(static_cast<std::uint32_t>(pair.light.size()),
                                    static_cast<std::uint32_t>(pair.camera.size()));
  return count > 0.0 && !pair.light.back().delta && !pair.camera.back().delta;
}

// `pairs` chunk by chunk: each pair's x into the chunk's lanes by gather_light_end and its y
// by gather_y(y, connects, c, lane), the connections counted as connect() counts them
// (connects[j]: whether lane j connects at all); then done(c, connects, first, all_lambertian),
// the chunk holding pairs[first ..), all_lambertian whether the lanes compute every BSDF in it.
template <class GatherY, class Done>
void for_each_chunk(const Scene& scene, const StrategyCounts& counts,
                    std::span<const ConnectionPair> pairs, TraceCounters& counters,
                    const GatherY& gather_y, const Done& done) {
  Chunk c;
  bool connects[kChunk];
  for (std::size_t first = 0; first < pairs.size(); first += kChunk) {
    c.size = std::min(kChunk, pairs.size() - first);
    bool all_lambertian = true;
    for (std::size_t j = 0; j < c.size; ++j) {
      const ConnectionPair& pair = pairs[first + j];
      connects[j] = pair_connects(counts, pair);
      counters.connections += connects[j] ? 1 : 0;
      all_lambertian &= gather_light_end(scene, pair.light.back(), connects[j], c, j);
      all_lambertian &= gather_y(pair.camera.back(), connects[j], c, j);
    }
    done(c, connects, first, all_lambertian);
  }
}

// The BSDF terms the lanes leave to bsdf_value, one at a time (`connects[j]` lanes only): where
// light_end(j) (x, null for an emitter point) is a surface that is not Lambertian, its f; where
// camera_end(j) (y, null for the lens) is not, its f and density.
template <class LightEnd, class CameraEnd>
void other_bsdfs(const Scene& scene, Chunk& c, const bool* connects, const LightEnd& light_end,
                 const CameraEnd& camera_end) {
  for (std::size_t j = 0; j < c.size; ++j) {
    if (!connects[j]) continue;
    const Vec3 w{c.w_x[j], c.w_y[j], c.w_z[j]};
    const PathVertex* x = light_end(j);
    if (x != nullptr && x->kind == VertexKind::kSurface) {
      const Material& m = scene.material(x->triangle);
      if (m.kind != MaterialKind::kDiffuse) {
        const Rgb f = bsdf_value(m, x->normal, x->to_previous, w).f;
        c.le_r[j] = f.r, c.le_g[j] = f.g, c.le_b[j] = f.b;
      }
    }
    const PathVertex* y = camera_end(j);
    if (y == nullptr) continue;
    const Material& m = scene.material(y->triangle);
    if (m.kind == MaterialKind::kDiffuse) continue;
    const BsdfValue b = bsdf_value(m, y->normal, y->to_previous, -w);
    c.f_r[j] = b.f.r, c.f_g[j] = b.f.g, c.f_b[j] = b.f.b;
    c.pdf_y[j] = b.pdf;
  }
}

// The gathered chunk's values into values[0 .. c.size) and, unless `weights` is null (the
// weight is then mis_weight's), the next-event weights into weights[0 .. c.size); light_end(j)
// and camera_end(j) are lane j's x and y, for the BSDFs that are not Lambertian (`all_lambertian`
// false when some are).
template <class LightEnd, class CameraEnd>
void finish(const Scene& scene, const StrategyCounts& counts, Chunk& c, bool all_lambertian,
            const bool* connects, const LightEnd& light_end, const CameraEnd& camera_end,
            Rgb* values, double* weights, TraceCounters& counters) {
  segments_and_ends(c);
  if (!all_lambertian) other_bsdfs(scene, c, connects, light_end, camera_end);
  double red[kChunk], green[kChunk], blue[kChunk];
  counters.skipped_zero +=
      weights != nullptr
          ? values_and_weights(c, counts.next_event, counts.emitter_hit, red, green, blue, weights)
          : scene::values(c, red, green, blue);
  for (std::size_t j = 0; j < c.size; ++j) values[j] = {red[j], green[j], blue[j]};
}

// The values of pairs with t >= 2 (next_event_values_and_weights, connection_values) and, unless
// `weights` is null, the next events' weights.
void values_of_pairs(const Scene& scene, const StrategyCounts& counts,
                     std::span<const ConnectionPair> pairs, std::span<Rgb> values, double* weights,
                     TraceCounters& counters) {
  for_each_chunk(
      scene, counts, pairs, counters,
      [&](const PathVertex& y, bool on, Chunk& c, std::size_t j) {
        return gather_camera_end(scene, y, on, c, j);
      },
      [&](Chunk& c, const bool* connects, std::size_t first, bool all_lambertian) {
        finish(
            scene, counts, c, all_lambertian, connects,
            [&](std::size_t j) { return &pairs[first + j].light.back(); },
            [&](std::size_t j) { return &pairs[first + j].camera.back(); }, values.data() + first,
            weights == nullptr ? nullptr : weights + first, counters);
      });
}

}  // namespace

void next_event_values_and_weights(const Scene& scene, const StrategyCounts& counts,
                                   std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                                   std::span<double> weights, TraceCounters& counters) {
  if (counts.next_event <= 0.0) {  // connect() returns 0 at once, counting nothing
    std::fill(values.begin(), values.end(), Rgb{});
    return;
  }
  values_of_pairs(scene, counts, pairs, values, weights.data(), counters);
}

void next_event_values_and_weights(const Scene& scene, const StrategyCounts& counts,
                                   const EmitterPoints& points,
                                   std::span<const PathVertex* const> camera_ends,
                                   std::span<Rgb> values, std::span<double> weights,
                                   TraceCounters& counters) {
  if (counts.next_event <= 0.0) {
    std::fill(values.begin(), values.end(), Rgb{});
    return;
  }
  Chunk c;
  bool connects[kChunk];
  c.size = points.size;
  bool all_lambertian = true;
  for (std::size_t j = 0; j < c.size; ++j) {
    const PathVertex& y = *camera_ends[j];
    connects[j] = !y.delta;  // an emitter point is never a delta vertex
    counters.connections += connects[j] ? 1 : 0;
    gather_emitter_point(points, j, connects[j], c, j);
    all_lambertian &= gather_camera_end(scene, y, connects[j], c, j);
  }
  finish(
      scene, counts, c, all_lambertian, connects,
      [](std::size_t) -> const PathVertex* { return nullptr; },
      [&](std::size_t j) { return camera_ends[j]; }, values.data(), weights.data(), counters);
}

bool all_camera_surface_ends(std::span<const ConnectionPair> pairs) {
  return std::all_of(pairs.begin(), pairs.end(), [](const ConnectionPair& p) {
    return !p.light.empty() && p.camera.size() >= 2;
  });
}

void connection_values(const Scene& scene, const StrategyCounts& counts,
                       std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                       TraceCounters& counters) {
  values_of_pairs(scene, counts, pairs, values, nullptr, counters);
}

bool all_light_tracing(std::span<const ConnectionPair> pairs) {
  return std::all_of(pairs.begin(), pairs.end(), [](const ConnectionPair& p) {
    return !p.light.empty() && p.camera.size() == 1;
  });
}

void light_tracing_values(const Scene& scene, const StrategyCounts& counts,
                          std::span<const ConnectionPair> pairs, std::span<Rgb> values,
                          std::span<std::optional<PixelPosition>> pixels, TraceCounters& counters) {
  for_each_chunk(
      scene, counts, pairs, counters,
      [](const PathVertex& y, bool on, Chunk& c, std::size_t j) {
        gather_lens(y, on, c, j);
        return true;
      },
      [&](Chunk& c, const bool* connects, std::size_t first, bool all_lambertian) {
        segments_and_ends(c);
        if (!all_lambertian) {
          other_bsdfs(
              scene, c, connects, [&](std::size_t j) { return &pairs[first + j].light.back(); },
              [](std::size_t) -> const PathVertex* { return nullptr; });
        }
        counters.skipped_zero += lens_values(c, scene.camera());
        for (std::size_t j = 0; j < c.size; ++j) {
          values[first + j] = {c.value_r[j], c.value_g[j], c.value_b[j]};
          // connect() sets its pixel once it has a segment: where its direction meets the film.
          if (!connects[j] || c.distance_squared[j] == 0.0) continue;
          pixels[first + j] = c.lands[j] != 0.0
                                  ? std::optional(PixelPosition{
                                        static_cast<std::uint32_t>(c.film_x[j]),
                                        static_cast<std::uint32_t>(c.film_y[j]), c.film_cos[j]})
                                  : std::nullopt;
        }
      });
}

}  // namespace pcbench::scene

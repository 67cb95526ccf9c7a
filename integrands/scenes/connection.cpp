#include "integrands/scenes/connection.h"

#include <cmath>

#include "integrands/scenes/bsdf.h"

namespace pcbench::scene {
namespace {

// A zero density marks a delta (specular) step; it must not zero the chain of ratios, whose
// terms through delta vertices are skipped anyway.
double remap0(double pdf) {
  return pdf != 0.0 ? pdf : 1.0;
}

// The segment joining x_{s-1} and y_{t-1} (s, t >= 1), computed once for the value and the
// weight of a connection.
struct Segment {
  Vec3 w;                             // unit, from the light side to the camera side
  double inv_distance_squared = 0.0;  // 0 when the two ends coincide
  double distance_squared = 0.0;
  double distance = 0.0;  // for the shadow ray's margin
};

Segment segment_between(const PathVertex& light_end, const PathVertex& camera_end) {
  const Vec3 d = camera_end.position - light_end.position;
  const double distance_squared = dot(d, d);
  if (distance_squared == 0.0) return {};
  const double distance = std::sqrt(distance_squared);
  const double inv_distance = 1.0 / distance;
  return {d * inv_distance, inv_distance * inv_distance, distance_squared, distance};
}

// Converts a solid-angle density at `v` towards its own predecessor into an area density at
// `previous`: v.to_previous is that direction, so this needs no square root.
double area_factor_to_previous(const PathVertex& v, const PathVertex& previous) {
  const Vec3 d = previous.position - v.position;
  return abs_cos_at(previous, v.to_previous) / dot(d, d);
}

// The reverse area densities a strategy changes. Every other vertex's pdf_rev, as its walk
// recorded it, is the density of sampling it from its successor given the successor's own
// successor, all inside the same subpath, so the connection leaves it valid. These four involve
// the other side: y_{t-1} and x_{s-1} are each sampled from the other end, and y_{t-2} and
// x_{s-2} from their successor having been reached through the connection.
struct JoinDensities {
  double camera_end = 0.0;     // y_{t-1}: from x_{s-1}; for s = 0, the emitters' position density
  double camera_before = 0.0;  // y_{t-2} (t >= 3; y_0's pdf_rev enters no ratio)
  double light_end = 0.0;      // x_{s-1}: from y_{t-1} (s >= 1)
  double light_before = 0.0;   // x_{s-2} (s >= 2)
};

// Strategy (0, t): y_{t-1} is on an emitter, which light paths start from by the emitter
// distribution and leave by cosine-weighted emission.
JoinDensities emitter_hit_densities(const Scene& scene, std::span<const PathVertex> camera) {
  const std::size_t t = camera.size();
  const PathVertex& pt = camera[t - 1];
  JoinDensities join;
  join.camera_end = scene.emitters().pdf_area(pt.triangle);
  if (t >= 3) {
    join.camera_before =
        emission_pdf(pt, pt.to_previous) * area_factor_to_previous(pt, camera[t - 2]);
  }
  return join;
}

// One end of a connection seen from the other: what it scatters (or emits) along the segment and
// its two solid-angle densities there, computed together for the value and the weight.
struct EndTerms {
  Rgb f;                   // x_{s-1}: BSDF or emitted radiance; y_{t-1} (t >= 2): BSDF
  double pdf_along = 0.0;  // of leaving along the segment towards the other end
  // Of leaving towards its own predecessor, having arrived along the segment (surfaces only).
  double pdf_back = 0.0;
};

// x_{s-1} (s >= 1); `w` points from it along the segment.
EndTerms light_end_terms(const Scene& scene, const PathVertex& qs, const Vec3& w) {
  if (qs.kind == VertexKind::kEmitter) {
    return {emitted_towards(scene, qs, w), emission_pdf(qs, w), 0.0};
  }
  const BsdfValue b = bsdf_value(scene.material(qs.triangle), qs.normal, qs.to_previous, w);
  return {b.f, b.pdf, b.pdf_reverse};
}

// y_{t-1} for t >= 2; `w` points from it along the segment.
EndTerms surface_camera_end_terms(const Scene& scene, const PathVertex& pt, const Vec3& w) {
  const BsdfValue b = bsdf_value(scene.material(pt.triangle), pt.normal, pt.to_previous, w);
  return {b.f, b.pdf, b.pdf_reverse};
}

// y_0 for t = 1: the pixel `w` goes through, if any, and its density (no f: the camera's
// importance enters the value through that density).
EndTerms camera_lens_terms(const Scene& scene, const Vec3& w, std::optional<PixelPosition>& where) {
  where = scene.camera().project(w);
  return {{}, where ? scene.camera().pixel_pdf(where->cos_theta) : 0.0, 0.0};
}

// Strategies with s, t >= 1: the four densities from the two ends' terms.
JoinDensities connection_densities(std::span<const PathVertex> light,
                                   std::span<const PathVertex> camera, const Segment& segment,
                                   const EndTerms& light_end, const EndTerms& camera_end) {
  const std::size_t s = light.size(), t = camera.size();
  const PathVertex& qs = light[s - 1];
  const PathVertex& pt = camera[t - 1];
  JoinDensities join;
  join.camera_end = light_end.pdf_along * abs_cos_at(pt, segment.w) * segment.inv_distance_squared;
  join.light_end = camera_end.pdf_along * abs_cos_at(qs, segment.w) * segment.inv_distance_squared;
  if (t >= 3) join.camera_before = camera_end.pdf_back * area_factor_to_previous(pt, camera[t - 2]);
  if (s >= 2) join.light_before = light_end.pdf_back * area_factor_to_previous(qs, light[s - 2]);
  return join;
}

// The path of strategy (s, t) in light order, z_0 .. z_{k-1} (z_j = x_j for j < s, then the
// camera prefix reversed), with the area density of sampling each vertex walking from the
// emitter: pdf_fwd on the light side, the reverse densities (the join's where the connection
// changed them) on the camera side.
class LightOrderPath {
 public:
  LightOrderPath(std::span<const PathVertex> light, std::span<const PathVertex> camera,
                 const JoinDensities& join)
      : light_(light), camera_(camera), join_(join) {}

  std::size_t size() const { return light_.size() + camera_.size(); }
  const PathVertex& at(std::size_t j) const {
    return j < light_.size() ? light_[j] : camera_[size() - 1 - j];
  }
  double light_density(std::size_t j) const {
    if (j < light_.size()) return light_[j].pdf_fwd;
    const std::size_t i = size() - 1 - j, t = camera_.size();  // camera index
    return i + 1 == t ? join_.camera_end : i + 2 == t ? join_.camera_before : camera_[i].pdf_rev;
  }

 private:
  std::span<const PathVertex> light_, camera_;
  const JoinDensities& join_;
};

// G(a, b): |cos| at both ends over the squared distance.
double geometry_term(const PathVertex& a, const PathVertex& b) {
  const Vec3 d = b.position - a.position;
  const double distance_squared = dot(d, d);
  if (distance_squared == 0.0) return 0.0;
  const Vec3 w = d * (1.0 / std::sqrt(distance_squared));
  return abs_cos_at(a, w) * abs_cos_at(b, w) / distance_squared;
}

// For each join i = 1 .. k-2 of the path, q*_i (ConnectionCountModel::count): the light side
// z_0 .. z_{i-1}'s contribution towards z_i without z_i's BSDF, extended one vertex at a time,
//     A_1 = Le(z_0 → z_1) G(z_0, z_1) / p(z_0),
//     A_{i+1} = A_i f(z_i; z_{i-1} → z_{i+1}) G(z_i, z_{i+1}) / p(z_i),
// computed from the path alone, so that every strategy that makes it sees the same values;
// -1 from the first specular vertex on.
void light_side_importances(const Scene& scene, const LightOrderPath& z,
                            std::span<double> importance) {
  const std::size_t k = z.size();
  Rgb a = emitted_towards(scene, z.at(0), z.at(1).position - z.at(0).position) *
          (geometry_term(z.at(0), z.at(1)) / remap0(z.light_density(0)));
  bool specular = false;
  for (std::size_t i = 1; i + 1 < k; ++i) {
    importance[i] = specular ? -1.0 : a.max_channel();
    const PathVertex& v = z.at(i);
    if (v.delta || v.kind != VertexKind::kSurface) specular = true;
    if (specular || i + 2 >= k) continue;
    const PathVertex& before = z.at(i - 1);
    const PathVertex& after = z.at(i + 1);
    const Rgb f =
        bsdf_value(scene.material(v.triangle), v.normal, normalize(before.position - v.position),
                   normalize(after.position - v.position))
            .f;
    a = a * f * (geometry_term(v, after) / remap0(z.light_density(i)));
  }
}

// Moving the join of a path across a vertex, from just after it to just before it, multiplies
// the strategy's density by this (a zero density marks a delta step, remap0).
double join_move_ratio(double pdf_rev, double pdf_fwd) {
  return remap0(pdf_rev) / remap0(pdf_fwd);
}

// Under counts without a model: the count of the strategy with `camera_vertices` camera
// vertices, `light_vertices` light ones (StrategyCounts::count).
double constant_count(const StrategyCounts& counts, std::size_t light_vertices,
                      std::size_t camera_vertices) {
  return counts.count(static_cast<std::uint32_t>(light_vertices),
                      static_cast<std::uint32_t>(camera_vertices));
}

// The balance heuristic n_own p_own / Σ n p over the strategies that make the same path, as
// 1 / (1 + Σ_others (n / n_own) p / p_own): moving the join one vertex along the path multiplies
// p by that vertex's reverse over its forward density (Veach's thesis, ch. 10). One loop over both
// subpaths; balance_weight takes the stored sums instead where it can.
double weight_by_loop(const Scene& scene, std::span<const PathVertex> light,
                      std::span<const PathVertex> camera, const JoinDensities& join,
                      const StrategyCounts& counts) {
  const std::size_t s = light.size(), t = camera.size();
  const std::size_t k = s + t;  // strategy (i, k - i) makes the same path
  constexpr std::size_t kMaxVertices = 64;
  double importance[kMaxVertices];
  const LightOrderPath z(light, camera, join);
  const bool path_counts = counts.model != nullptr && k >= 3 && k <= kMaxVertices;
  if (path_counts) light_side_importances(scene, z, std::span<double>(importance, k));
  auto count = [&](std::size_t light_vertices) {
    const double constant = counts.count(static_cast<std::uint32_t>(light_vertices),
                                         static_cast<std::uint32_t>(k - light_vertices));
    if (!path_counts || light_vertices == 0 || k - light_vertices < 2 || constant <= 0.0 ||
        (light_vertices == 1 && !counts.model->counts_next_event())) {
      return constant;
    }
    return counts.model->count(importance[light_vertices], z.at(light_vertices).position, constant);
  };
  // Each end is sampled from the other side here, so it is never a delta step of this path.
  auto camera_delta = [&](std::size_t i) { return i + 1 < t && camera[i].delta; };
  auto camera_rev = [&](std::size_t i) {
    return i + 1 == t ? join.camera_end : i + 2 == t ? join.camera_before : camera[i].pdf_rev;
  };
  auto light_delta = [&](std::size_t i) { return i + 1 < s && light[i].delta; };
  auto light_rev = [&](std::size_t i) {
    return i + 1 == s ? join.light_end : i + 2 == s ? join.light_before : light[i].pdf_rev;
  };

  double others = 0.0;  // Σ n p / p_own over the other strategies, times n_own
  double ratio = 1.0;
  for (std::size_t i = t - 1; i > 0; --i) {  // moving the join towards the camera: (k - i, i)
    ratio *= join_move_ratio(camera_rev(i), camera[i].pdf_fwd);
    if (!camera_delta(i) && !camera[i - 1].delta) others += ratio * count(k - i);
  }
  ratio = 1.0;
  const bool point_light = s > 0 && light[0].point_light;
  for (std::size_t i = s; i-- > 0;) {  // moving the join towards the emitter: (i, k - i)
    ratio *= join_move_ratio(light_rev(i), light[i].pdf_fwd);
    const bool before_delta = i > 0 ? light[i - 1].delta : point_light;
    if (!light_delta(i) && !before_delta) others += ratio * count(i);
  }
  const double own = count(s);
  return own / (own + others);  // = 1 / (1 + others / own), with one division
}

// weight_by_loop's sums, nested from the join outwards: its camera-side terms are
//   q_{t-1} (n_{t-1} + q_{t-2} (n_{t-2} + S_{t-3})),   q_i = rev_i / fwd_i, n_i the count of the
// strategy with i camera vertices (0 where a delta vertex rules it out), and S_{t-3} the sum
// over i <= t-3, which involves only densities the camera walk recorded: y_{t-3}'s weight_sum.
// The light side likewise. The join's own densities enter only the two outer levels.
double weight_from_sums(std::span<const PathVertex> light, std::span<const PathVertex> camera,
                        const JoinDensities& join, const StrategyCounts& counts) {
  const std::size_t s = light.size(), t = camera.size(), k = s + t;
  double others = 0.0;
  if (t >= 2) {  // the strategies with i = t-1, t-2, ... camera vertices
    const double end = camera[t - 2].delta ? 0.0 : constant_count(counts, k - (t - 1), t - 1);
    double before = 0.0;
    if (t >= 3) {
      const bool possible = !camera[t - 2].delta && !camera[t - 3].delta;
      before = join_move_ratio(join.camera_before, camera[t - 2].pdf_fwd) *
               ((possible ? constant_count(counts, k - (t - 2), t - 2) : 0.0) +
                camera[t - 3].weight_sum);
    }
    others += join_move_ratio(join.camera_end, camera[t - 1].pdf_fwd) * (end + before);
  }
  if (s >= 1) {  // the strategies with i = s-1, s-2, ... light vertices
    auto after_delta = [&](std::size_t i) {
      return i > 0 ? light[i - 1].delta : light[0].point_light;
    };
    const double end = after_delta(s - 1) ? 0.0 : constant_count(counts, s - 1, k - (s - 1));
    double before = 0.0;
    if (s >= 2) {
      const bool possible = !light[s - 2].delta && !after_delta(s - 2);
      before = join_move_ratio(join.light_before, light[s - 2].pdf_fwd) *
               ((possible ? constant_count(counts, s - 2, k - (s - 2)) : 0.0) +
                (s >= 3 ? light[s - 3].weight_sum : 0.0));
    }
    others += join_move_ratio(join.light_end, light[s - 1].pdf_fwd) * (end + before);
  }
  const double own = constant_count(counts, s, t);
  return own / (own + others);
}

double balance_weight(const Scene& scene, std::span<const PathVertex> light,
                      std::span<const PathVertex> camera, const JoinDensities& join,
                      const StrategyCounts& counts) {
  return weight_sums_stored(light, camera, counts)
             ? weight_from_sums(light, camera, join, counts)
             : weight_by_loop(scene, light, camera, join, counts);
}

}  // namespace

void store_camera_weight_sums(std::span<PathVertex> camera, const StrategyCounts& counts) {
  if (counts.model != nullptr || camera.empty()) return;
  // y_0 is never a join's far side (t >= 1); y_m for 1 <= m <= n-3 has its final pdf_rev (the
  // walk sets y_m's when it scatters at y_{m+1}), and a weight reads y_{t-3}'s for t <= n.
  camera[0].weight_sum = 0.0;
  double sum = 0.0;
  for (std::size_t m = 1; m + 2 < camera.size(); ++m) {
    const bool possible = !camera[m].delta && !camera[m - 1].delta;
    // The strategy with m camera vertices has at least three light vertices here: its count
    // is light tracing's for m = 1, else a connection's.
    const double n = possible ? (m == 1 ? counts.light_tracing : counts.connection) : 0.0;
    sum = join_move_ratio(camera[m].pdf_rev, camera[m].pdf_fwd) * (n + sum);
    camera[m].weight_sum = sum;
  }
}

void store_light_weight_sums(std::span<PathVertex> light, const StrategyCounts& counts) {
  if (counts.model != nullptr) return;
  double sum = 0.0;
  for (std::size_t m = 0; m + 2 < light.size(); ++m) {
    const bool after_delta = m > 0 ? light[m - 1].delta : light[0].point_light;
    const bool possible = !light[m].delta && !after_delta;
    // The strategy with m light vertices has at least two camera vertices (an emitter hit for
    // m = 0, a next event for m = 1).
    const double n = possible ? (m == 0   ? counts.emitter_hit
                                 : m == 1 ? counts.next_event
                                          : counts.connection)
                              : 0.0;
    sum = join_move_ratio(light[m].pdf_rev, light[m].pdf_fwd) * (n + sum);
    light[m].weight_sum = sum;
  }
}

double mis_weight(const Scene& scene, std::span<const PathVertex> light,
                  std::span<const PathVertex> camera, const StrategyCounts& counts) {
  if (light.empty()) {
    return balance_weight(scene, light, camera, emitter_hit_densities(scene, camera), counts);
  }
  const Segment segment = segment_between(light.back(), camera.back());
  const EndTerms light_end = light_end_terms(scene, light.back(), segment.w);
  std::optional<PixelPosition> where;
  const EndTerms camera_end = camera.size() >= 2
                                  ? surface_camera_end_terms(scene, camera.back(), -segment.w)
                                  : camera_lens_terms(scene, -segment.w, where);
  return balance_weight(scene, light, camera,
                        connection_densities(light, camera, segment, light_end, camera_end),
                        counts);
}

Rgb connect(const Scene& scene, std::span<const PathVertex> light,
            std::span<const PathVertex> camera, const StrategyCounts& counts,
            const ConnectOptions& options, TraceCounters& counters,
            std::optional<PixelPosition>* pixel) {
  const std::size_t s = light.size(), t = camera.size();
  if (counts.count(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(t)) <= 0.0) {
    return {};
  }
  if (s == 0) {  // the camera subpath found an emitter by itself
    const PathVertex& pt = camera[t - 1];
    if (pt.kind != VertexKind::kSurface) return {};
    const Triangle& tri = scene.triangle(pt.triangle);
    if (tri.emission.is_black() || dot(pt.normal, pt.to_previous) <= 0.0) return {};
    const Rgb value = pt.beta * tri.emission;
    if (!options.weighted) return value;
    return value *
           balance_weight(scene, light, camera, emitter_hit_densities(scene, camera), counts);
  }
  const PathVertex& qs = light[s - 1];
  const PathVertex& pt = camera[t - 1];
  if (qs.delta || pt.delta) return {};
  ++counters.connections;
  const Segment segment = segment_between(qs, pt);
  if (segment.inv_distance_squared == 0.0) return {};
  // Set up here, from the segment's length, so that its division overlaps the ends' BSDFs.
  const Scene::ShadowRay shadow =
      scene.shadow_ray(qs.position, pt.position, segment.distance_squared, segment.distance);
  const Vec3& w = segment.w;  // from the light side to the camera side
  const EndTerms light_end = light_end_terms(scene, qs, w);
  EndTerms camera_end;
  Rgb value;
  if (t == 1) {
    std::optional<PixelPosition> where;
    camera_end = camera_lens_terms(scene, -w, where);
    if (pixel) *pixel = where;
    if (!where) return {};
    value = qs.beta * light_end.f *
            (abs_cos_at(qs, w) * segment.inv_distance_squared * camera_end.pdf_along);
  } else {
    camera_end = surface_camera_end_terms(scene, pt, -w);
    value = qs.beta * light_end.f * camera_end.f * pt.beta *
            (abs_cos_at(qs, w) * abs_cos_at(pt, w) * segment.inv_distance_squared);
  }
  if (value.is_black()) {
    ++counters.skipped_zero;
    return {};
  }
  if (options.visibility) {
    if (scene.traits().convex_enclosure) {
      ++counters.skipped_convex;
    } else {
      ++counters.shadow_rays;
      if (scene.occluded(shadow)) {
        ++counters.occluded;
        return {};
      }
    }
  }
  if (!options.weighted) return value;
  return value * balance_weight(scene, light, camera,
                                connection_densities(light, camera, segment, light_end, camera_end),
                                counts);
}

}  // namespace pcbench::scene

// The balance weights of a row's unblocked connections in SIMD lanes (connection_weights,
// connection_lanes.h): mis_weight()'s arithmetic for strategies with s >= 1 and t >= 2 whose
// weight comes from the subpaths' stored sums (weight_from_sums in connection.cpp) and whose ends
// are Lambertian surfaces or an emitter. One at a time, each weight recomputed the segment, took
// both ends' BSDF densities through bsdf_value's switch and made eight divisions and a square root
// in a row; here the gathers stay one at a time and the arithmetic runs across the connections.
// The order of operations is mis_weight()'s, the file is built without contraction
// (CMakeLists.txt), so the weights are its own to the bit (tests/connection_lanes_test.cpp).
#include <algorithm>
#include <cmath>

#include "base/lane_select.h"
#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/connection_lanes.h"
#include "integrands/scenes/lane_vec3.h"

namespace pcbench::scene {
namespace {

constexpr std::size_t kChunk = 64;  // connections a pass of the lanes takes

// One side's terms of weight_from_sums (connection.cpp) beyond the join, in lanes: the strategy
// one vertex past the join (0 where a delta vertex rules it out) and the end's forward density;
// whether there is a second level, and then the count of the strategy two vertices past the join
// plus the stored sum beyond it, the predecessor's forward density, and |cos| at the predecessor
// towards the end and its position (area_factor_to_previous).
struct SideTerms {
  double end[kChunk], end_fwd[kChunk];
  double has_before[kChunk], before_sum[kChunk], before_fwd[kChunk];
  double before_cos[kChunk], before_x[kChunk], before_y[kChunk], before_z[kChunk];
};

// A chunk's weights' inputs in structure-of-arrays form: x = x_{s-1}, y = y_{t-1}.
struct WeightChunk {
  std::size_t size = 0;
  double x_x[kChunk], x_y[kChunk], x_z[kChunk];
  // An emitter x's normal (0 at a point light); a surface x's turned to wo (bsdf_detail::facing).
  double xn_x[kChunk], xn_y[kChunk], xn_z[kChunk];
  double point_light[kChunk];  // 1 or 0
  // A surface x's cosine of wo against that normal (its reverse density's; bsdf_value's first
  // same-side test); 1 for an emitter, which has no reverse density here.
  double x_wo_cos[kChunk];
  double y_x[kChunk], y_y[kChunk], y_z[kChunk];
  double yn_x[kChunk], yn_y[kChunk], yn_z[kChunk];  // y's normal
  double yf_x[kChunk], yf_y[kChunk], yf_z[kChunk];  // y's normal turned to wo
  double y_wo_cos[kChunk];
  // The camera side's terms beyond y_{t-1}, the light side's beyond x_{s-1}.
  SideTerms camera, light;
  double own[kChunk];  // the strategy's own count
  double weight[kChunk];
};

// join_move_ratio (connection.cpp): a zero density stands for a delta step.
[[gnu::always_inline]] inline double move_ratio(double pdf_rev, double pdf_fwd) {
  return lane_select(pdf_rev != 0.0, pdf_rev, 1.0) / lane_select(pdf_fwd != 0.0, pdf_fwd, 1.0);
}

// One side's share of weight_from_sums for lane j: the end at `end_position`, the join's density
// there (`end_density`) and the end's reverse density towards its predecessor (`pdf_back`).
[[gnu::always_inline]] inline double side_sum(const SideTerms& side, std::size_t j,
                                              const Vec3& end_position, double end_density,
                                              double pdf_back) {
  const Vec3 to_before = Vec3{side.before_x[j], side.before_y[j], side.before_z[j]} - end_position;
  const double before_density = pdf_back * (side.before_cos[j] / dot(to_before, to_before));
  const double before =
      lane_select(side.has_before[j] != 0.0,
                  move_ratio(before_density, side.before_fwd[j]) * side.before_sum[j], 0.0);
  return move_ratio(end_density, side.end_fwd[j]) * (side.end[j] + before);
}

// mis_weight()'s steps for lane j: segment_between, light_end_terms (emission_pdf, or a
// Lambertian bsdf_value's two densities), surface_camera_end_terms, connection_densities,
// weight_from_sums.
[[gnu::target_clones("avx512f", "avx2", "default")]] void weigh(WeightChunk& c) {
  for (std::size_t j = 0; j < c.size; ++j) {
    const Vec3 x{c.x_x[j], c.x_y[j], c.x_z[j]};
    const Vec3 y{c.y_x[j], c.y_y[j], c.y_z[j]};
    const Vec3 d = y - x;
    const double distance = std::sqrt(dot(d, d));
    const double inv_distance = 1.0 / distance;
    const Vec3 w = d * inv_distance;
    const double inv_distance_squared = inv_distance * inv_distance;

    const double cos_at_x = dot(Vec3{c.xn_x[j], c.xn_y[j], c.xn_z[j]}, w);
    const bool point_light = c.point_light[j] != 0.0;
    const bool x_same = (c.x_wo_cos[j] > 0.0) & (cos_at_x > 0.0);
    const double x_pdf_along =
        lane_select(point_light, 1.0 / (4.0 * kPi), lane_select(x_same, cos_at_x * kInvPi, 0.0));
    const double x_pdf_back = lane_select(x_same, c.x_wo_cos[j] * kInvPi, 0.0);
    const double cos_x = lane_select(point_light, 1.0, std::abs(cos_at_x));

    const double y_wi_cos = dot(Vec3{c.yf_x[j], c.yf_y[j], c.yf_z[j]}, -w);
    const bool y_same = (c.y_wo_cos[j] > 0.0) & (y_wi_cos > 0.0);
    const double y_pdf_along = lane_select(y_same, y_wi_cos * kInvPi, 0.0);
    const double y_pdf_back = lane_select(y_same, c.y_wo_cos[j] * kInvPi, 0.0);
    const double cos_y = std::abs(dot(Vec3{c.yn_x[j], c.yn_y[j], c.yn_z[j]}, w));

    const double camera_end = x_pdf_along * cos_y * inv_distance_squared;
    const double light_end = y_pdf_along * cos_x * inv_distance_squared;
    double others = 0.0;
    others += side_sum(c.camera, j, y, camera_end, y_pdf_back);
    others += side_sum(c.light, j, x, light_end, x_pdf_back);
    c.weight[j] = c.own[j] / (c.own[j] + others);
  }
}

bool lambertian(const Scene& scene, const PathVertex& v) {
  return v.kind == VertexKind::kSurface &&
         scene.material(v.triangle).kind == MaterialKind::kDiffuse;
}

// Whether the lanes weigh `pair` (else mis_weight() does): a weight from stored sums, an emitter
// or a Lambertian light end, a Lambertian camera end.
bool in_lanes(const Scene& scene, const StrategyCounts& counts, const ConnectionPair& pair) {
  return pair.light.size() >= 1 && pair.camera.size() >= 2 &&
         weight_sums_stored(pair.light, pair.camera, counts) &&
         (pair.light.back().kind == VertexKind::kEmitter || lambertian(scene, pair.light.back())) &&
         lambertian(scene, pair.camera.back());
}

// Lane j of one side's terms: `end` and the end vertex; `before`, its predecessor, when the
// weight has a second level on this side, with `before_sum` the count and stored sum beyond it.
void put_side(SideTerms& side, std::size_t j, double end, const PathVertex& end_vertex,
              const PathVertex* before, double before_sum) {
  side.end[j] = end;
  side.end_fwd[j] = end_vertex.pdf_fwd;
  side.has_before[j] = before != nullptr ? 1.0 : 0.0;
  side.before_sum[j] = before_sum;
  if (before == nullptr) {
    side.before_fwd[j] = side.before_cos[j] = 0.0;
    put(side.before_x, side.before_y, side.before_z, j, {});
    return;
  }
  side.before_fwd[j] = before->pdf_fwd;
  side.before_cos[j] = abs_cos_at(*before, end_vertex.to_previous);
  put(side.before_x, side.before_y, side.before_z, j, before->position);
}

// Lane j's inputs from `pair` (in_lanes), weight_from_sums' terms as it forms them.
void gather(const StrategyCounts& counts, const ConnectionPair& pair, WeightChunk& c,
            std::size_t j) {
  const std::span<const PathVertex> light = pair.light, camera = pair.camera;
  const std::size_t s = light.size(), t = camera.size(), k = s + t;
  auto count = [&](std::size_t light_vertices, std::size_t camera_vertices) {
    return counts.count(static_cast<std::uint32_t>(light_vertices),
                        static_cast<std::uint32_t>(camera_vertices));
  };

  const PathVertex& x = light[s - 1];
  put(c.x_x, c.x_y, c.x_z, j, x.position);
  c.point_light[j] = x.point_light ? 1.0 : 0.0;
  if (x.kind == VertexKind::kEmitter) {
    put(c.xn_x, c.xn_y, c.xn_z, j, x.normal);
    c.x_wo_cos[j] = 1.0;
  } else {
    const Vec3 facing = bsdf_detail::facing(x.normal, x.to_previous);
    put(c.xn_x, c.xn_y, c.xn_z, j, facing);
    c.x_wo_cos[j] = dot(facing, x.to_previous);
  }
  const PathVertex& y = camera[t - 1];
  put(c.y_x, c.y_y, c.y_z, j, y.position);
  put(c.yn_x, c.yn_y, c.yn_z, j, y.normal);
  const Vec3 facing = bsdf_detail::facing(y.normal, y.to_previous);
  put(c.yf_x, c.yf_y, c.yf_z, j, facing);
  c.y_wo_cos[j] = dot(facing, y.to_previous);

  // The camera side: strategies with t-1, t-2, ... camera vertices.
  const PathVertex* camera_before = t >= 3 ? &camera[t - 2] : nullptr;
  double camera_before_sum = 0.0;
  if (camera_before != nullptr) {
    const bool possible = !camera_before->delta && !camera[t - 3].delta;
    camera_before_sum = (possible ? count(k - (t - 2), t - 2) : 0.0) + camera[t - 3].weight_sum;
  }
  put_side(c.camera, j, camera[t - 2].delta ? 0.0 : count(k - (t - 1), t - 1), y, camera_before,
           camera_before_sum);

  // The light side: strategies with s-1, s-2, ... light vertices (none after a point light).
  auto after_delta = [&](std::size_t i) {
    return i > 0 ? light[i - 1].delta : light[0].point_light;
  };
  const PathVertex* light_before = s >= 2 ? &light[s - 2] : nullptr;
  double light_before_sum = 0.0;
  if (light_before != nullptr) {
    const bool possible = !light_before->delta && !after_delta(s - 2);
    light_before_sum =
        (possible ? count(s - 2, k - (s - 2)) : 0.0) + (s >= 3 ? light[s - 3].weight_sum : 0.0);
  }
  put_side(c.light, j, after_delta(s - 1) ? 0.0 : count(s - 1, k - (s - 1)), x, light_before,
           light_before_sum);
  c.own[j] = count(s, t);
}

}  // namespace

void connection_weights(const Scene& scene, const StrategyCounts& counts,
                        std::span<const ConnectionPair> pairs, std::span<const std::uint32_t> which,
                        std::span<double> weights) {
  WeightChunk c;
  std::uint32_t lane_of[kChunk];  // which[] index of each lane
  for (std::size_t first = 0; first < which.size(); first += kChunk) {
    const std::size_t end = std::min(which.size(), first + kChunk);
    c.size = 0;
    for (std::size_t i = first; i < end; ++i) {
      const ConnectionPair& pair = pairs[which[i]];
      if (!in_lanes(scene, counts, pair)) {
        weights[i] = mis_weight(scene, pair.light, pair.camera, counts);
        continue;
      }
      gather(counts, pair, c, c.size);
      lane_of[c.size++] = static_cast<std::uint32_t>(i);
    }
    weigh(c);
    for (std::size_t j = 0; j < c.size; ++j) weights[lane_of[j]] = c.weight[j];
  }
}

}  // namespace pcbench::scene

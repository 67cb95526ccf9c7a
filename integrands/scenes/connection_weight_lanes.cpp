// The balance weights of a row's unblocked connections in SIMD lanes (connection_weights,
// connection_lanes.h): mis_weight()'s arithmetic for strategies with s >= 1 and t >= 2 whose
// weight comes from the subpaths' stored sums (weight_from_sums in connection.cpp) and whose ends
// are Lambertian surfaces or an emitter. One at a time, each weight recomputed the segment, took
// both ends' BSDF densities through bsdf_value's switch and made seven divisions and a square root
// in a row; here the gathers stay one at a time and the arithmetic runs across the connections.
// The order of operations is mis_weight()'s, the file is built without contraction
// (CMakeLists.txt), so the weights are its own to the bit (tests/connection_lanes_test.cpp).
#include <algorithm>
#include <cmath>

#include "base/lane_select.h"
#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/connection_lanes.h"

namespace pcbench::scene {
namespace {

constexpr std::size_t kChunk = 64;  // connections a pass of the lanes takes

// A chunk's weights' inputs in structure-of-arrays form: x = x_{s-1}, y = y_{t-1}; "c_" the
// camera side's terms beyond the join, "l_" the light side's, as weight_from_sums nests them.
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
  // y_{t-2} (t >= 3) and x_{s-2} (s >= 2): |cos| there towards the end's side and the position,
  // for area_factor_to_previous.
  double cp_cos[kChunk], cp_x[kChunk], cp_y[kChunk], cp_z[kChunk];
  double lp_cos[kChunk], lp_x[kChunk], lp_y[kChunk], lp_z[kChunk];
  // weight_from_sums' terms: the strategy one vertex past the join (0 where a delta vertex rules
  // it out), whether there is a second level, its count plus the stored sum beyond it, and the
  // forward densities the join's reverse ones are divided by.
  double c_end[kChunk], c_has_before[kChunk], c_before_sum[kChunk];
  double c_end_fwd[kChunk], c_before_fwd[kChunk];
  double l_end[kChunk], l_has_before[kChunk], l_before_sum[kChunk];
  double l_end_fwd[kChunk], l_before_fwd[kChunk];
  double own[kChunk];  // the strategy's own count
  double weight[kChunk];
};

// join_move_ratio (connection.cpp): a zero density stands for a delta step.
[[gnu::always_inline]] inline double move_ratio(double pdf_rev, double pdf_fwd) {
  return lane_select(pdf_rev != 0.0, pdf_rev, 1.0) / lane_select(pdf_fwd != 0.0, pdf_fwd, 1.0);
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
    const Vec3 to_cp = Vec3{c.cp_x[j], c.cp_y[j], c.cp_z[j]} - y;
    const double camera_before = y_pdf_back * (c.cp_cos[j] / dot(to_cp, to_cp));
    const Vec3 to_lp = Vec3{c.lp_x[j], c.lp_y[j], c.lp_z[j]} - x;
    const double light_before = x_pdf_back * (c.lp_cos[j] / dot(to_lp, to_lp));

    const double c_before =
        lane_select(c.c_has_before[j] != 0.0,
                    move_ratio(camera_before, c.c_before_fwd[j]) * c.c_before_sum[j], 0.0);
    const double l_before =
        lane_select(c.l_has_before[j] != 0.0,
                    move_ratio(light_before, c.l_before_fwd[j]) * c.l_before_sum[j], 0.0);
    double others = 0.0;
    others += move_ratio(camera_end, c.c_end_fwd[j]) * (c.c_end[j] + c_before);
    others += move_ratio(light_end, c.l_end_fwd[j]) * (c.l_end[j] + l_before);
    c.weight[j] = c.own[j] / (c.own[j] + others);
  }
}

void put(double* x, double* y, double* z, std::size_t j, const Vec3& v) {
  x[j] = v.x, y[j] = v.y, z[j] = v.z;
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
  c.c_end[j] = camera[t - 2].delta ? 0.0 : count(k - (t - 1), t - 1);
  c.c_end_fwd[j] = y.pdf_fwd;
  c.c_has_before[j] = t >= 3 ? 1.0 : 0.0;
  if (t >= 3) {
    const PathVertex& before = camera[t - 2];
    c.cp_cos[j] = abs_cos_at(before, y.to_previous);
    put(c.cp_x, c.cp_y, c.cp_z, j, before.position);
    const bool possible = !before.delta && !camera[t - 3].delta;
    c.c_before_sum[j] = (possible ? count(k - (t - 2), t - 2) : 0.0) + camera[t - 3].weight_sum;
    c.c_before_fwd[j] = before.pdf_fwd;
  } else {
    c.cp_cos[j] = c.cp_x[j] = c.cp_y[j] = c.cp_z[j] = 0.0;
    c.c_before_sum[j] = c.c_before_fwd[j] = 0.0;
  }

  // The light side: strategies with s-1, s-2, ... light vertices.
  auto after_delta = [&](std::size_t i) {
    return i > 0 ? light[i - 1].delta : light[0].point_light;
  };
  c.l_end[j] = after_delta(s - 1) ? 0.0 : count(s - 1, k - (s - 1));
  c.l_end_fwd[j] = x.pdf_fwd;
  c.l_has_before[j] = s >= 2 ? 1.0 : 0.0;
  if (s >= 2) {
    const PathVertex& before = light[s - 2];
    c.lp_cos[j] = abs_cos_at(before, x.to_previous);
    put(c.lp_x, c.lp_y, c.lp_z, j, before.position);
    const bool possible = !before.delta && !after_delta(s - 2);
    c.l_before_sum[j] =
        (possible ? count(s - 2, k - (s - 2)) : 0.0) + (s >= 3 ? light[s - 3].weight_sum : 0.0);
    c.l_before_fwd[j] = before.pdf_fwd;
  } else {
    c.lp_cos[j] = c.lp_x[j] = c.lp_y[j] = c.lp_z[j] = 0.0;
    c.l_before_sum[j] = c.l_before_fwd[j] = 0.0;
  }
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

#include "estimators/scene/light_importance_lanes.h"

#include <cmath>

#include "base/lane_select.h"
#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/path_vertex.h"

namespace pcbench::scene {

double light_importance(const Scene& scene, const PathVertex& x, const PathVertex& y) {
  if (x.delta) return 0.0;
  const Vec3 d = y.position - x.position;
  const double distance_squared = dot(d, d);
  if (distance_squared == 0.0) return 0.0;
  const Vec3 w = d * (1.0 / std::sqrt(distance_squared));
  const Rgb f = x.kind == VertexKind::kEmitter
                    ? emitted_towards(scene, x, w)
                    : bsdf_value(scene.material(x.triangle), x.normal, x.to_previous, w).f;
  return (x.beta * f).max_channel() * (abs_cos_at(x, w) * abs_cos_at(y, w) / distance_squared);
}

namespace {

struct Candidates {
  const double *x, *y, *z, *nx, *ny, *nz, *weight, *point_light, *lanes;
};

// light_importance's arithmetic for n candidates at one end y, a candidate per lane. Built for
// AVX-512, AVX2 and SSE2 (the widest the machine has, chosen at run time), without contraction
// and without errno (CMakeLists.txt), so each lane rounds as the scalar code does.
[[gnu::target_clones("avx512f", "avx2", "default")]] void weigh(
    const Candidates& c, std::size_t n, Vec3 end, Vec3 end_normal, bool end_cos_one,
    double* __restrict q, double* __restrict distance_squared, double* __restrict distance) {
  // The arrays apart from each other and from the end (taken by value), so that the loop needs
  // no alias checks: without them GCC reloaded the end every step and kept the loop scalar.
  const double* __restrict x = c.x;
  const double* __restrict y = c.y;
  const double* __restrict z = c.z;
  const double* __restrict nx = c.nx;
  const double* __restrict ny = c.ny;
  const double* __restrict nz = c.nz;
  const double* __restrict weight = c.weight;
  const double* __restrict point_light = c.point_light;
  const double* __restrict lanes = c.lanes;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d{end.x - x[i], end.y - y[i], end.z - z[i]};
    const double d2 = dot(d, d);
    const double length = std::sqrt(d2);
    const Vec3 w = d * (1.0 / length);
    // The side the candidate lights: a Lambertian surface's facing normal (|cos| is the same for
    // either sign of the normal), a triangle emitter's own; a point light lights every side.
    const double cos_at_x = nx[i] * w.x + ny[i] * w.y + nz[i] * w.z;
    const bool point = point_light[i] != 0.0;
    const double cos_x = lane_select(point, 1.0, std::abs(cos_at_x));
    const double cos_y = lane_select(end_cos_one, 1.0, std::abs(dot(end_normal, w)));
    const bool lit = point | (cos_at_x > 0.0);
    const double value = lane_select(lit, weight[i], 0.0) * (cos_x * cos_y / d2);
    const bool keep = (lanes[i] != 0.0) & (d2 != 0.0);
    q[i] = lane_select(keep, value, 0.0);
    distance_squared[i] = d2;
    distance[i] = length;
  }
}

}  // namespace

void LightImportanceLanes::assign(const Scene& scene, const LightPool& pool,
                                  std::span<const LightVertexRef> vertices) {
  for (std::vector<double>* v :
       {&x_, &y_, &z_, &nx_, &ny_, &nz_, &weight_, &point_light_, &lanes_}) {
    v->resize(vertices.size());
  }
  directional_.clear();
  directional_vertex_.clear();
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const PathVertex& x = light_prefix(pool, vertices[i]).back();
    x_[i] = x.position.x;
    y_[i] = x.position.y;
    z_[i] = x.position.z;
    Vec3 lit_side{};
    double weight = 0.0;
    bool lanes = !x.delta;
    if (x.delta) {
      // q = 0: no connection uses a specular vertex.
    } else if (x.kind == VertexKind::kEmitter) {
      const Rgb emitted = x.point_light ? scene.description().point_lights[x.triangle].intensity
                                        : scene.triangle(x.triangle).emission;
      lit_side = x.normal;
      weight = (x.beta * emitted).max_channel();
    } else if (const Material& m = scene.material(x.triangle); m.kind == MaterialKind::kDiffuse) {
      // bsdf_value's f: albedo / π where wo and wi are both on the facing normal's side.
      lit_side = bsdf_detail::facing(x.normal, x.to_previous);
      const bool wo_in_front = dot(lit_side, x.to_previous) > 0.0;
      weight = wo_in_front ? (x.beta * (m.albedo * kInvPi)).max_channel() : 0.0;
    } else {
      lanes = false;
      directional_.push_back(static_cast<std::uint32_t>(i));
      directional_vertex_.push_back(&x);
    }
    nx_[i] = lit_side.x;
    ny_[i] = lit_side.y;
    nz_[i] = lit_side.z;
    weight_[i] = weight;
    point_light_[i] = x.point_light ? 1.0 : 0.0;
    lanes_[i] = lanes ? 1.0 : 0.0;
  }
}

void LightImportanceLanes::at(const Scene& scene, const PathVertex& y,
                              LightImportances& out) const {
  const std::size_t n = size();
  out.q.resize(n);
  out.distance_squared.resize(n);
  out.distance.resize(n);
  const Candidates c{x_.data(),  y_.data(),      z_.data(),           nx_.data(),   ny_.data(),
                     nz_.data(), weight_.data(), point_light_.data(), lanes_.data()};
  // abs_cos_at(y, w): 1 at the camera or a point light.
  const bool end_cos_one = y.kind == VertexKind::kCamera || y.point_light;
  weigh(c, n, y.position, y.normal, end_cos_one, out.q.data(), out.distance_squared.data(),
        out.distance.data());
  for (std::size_t k = 0; k < directional_.size(); ++k) {
    out.q[directional_[k]] = light_importance(scene, *directional_vertex_[k], y);
  }
}

}  // namespace pcbench::scene

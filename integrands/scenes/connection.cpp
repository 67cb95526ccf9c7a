#include "integrands/scenes/connection.h"

#include <array>
#include <cmath>

#include "integrands/scenes/bsdf.h"

namespace pcbench::scene {
namespace {

constexpr std::size_t kMaxVertices = 66;  // max_length <= 64, plus the camera and the emitter

struct MisVertex {
  double pdf_fwd = 0.0;
  double pdf_rev = 0.0;
  bool delta = false;
};

// A zero density marks a delta (specular) step; it must not zero the chain of ratios, whose
// terms through delta vertices are skipped anyway.
double remap0(double pdf) {
  return pdf != 0.0 ? pdf : 1.0;
}

// Density of the camera side sampling emitter point `v` by chance (s = 0): the emitter
// distribution's area density there.
double emitter_position_pdf(const Scene& scene, const PathVertex& v) {
  return scene.emitters().pdf_area(v.triangle);
}

// Density of leaving emitter point `v` towards `next` by emission sampling (area at next).
double emission_pdf_towards(const Scene& scene, const PathVertex& v, const PathVertex& next) {
  PathVertex as_emitter = v;
  as_emitter.kind = VertexKind::kEmitter;
  return pdf_area_towards(scene, as_emitter, nullptr, next);
}

// f at a vertex for light arriving from `from` and leaving towards `to` (both points); for an
// emitter vertex of a light subpath, the emitted radiance towards `to`.
Rgb scattering(const Scene& scene, const PathVertex& v, const Vec3& to) {
  if (v.kind == VertexKind::kEmitter) return emitted_towards(scene, v, to);
  return bsdf_eval(scene.material(v.triangle), v.normal, v.to_previous, normalize(to - v.position));
}

}  // namespace

double mis_weight(const Scene& scene, std::span<const PathVertex> light,
                  std::span<const PathVertex> camera, const StrategyCounts& counts) {
  const std::size_t s = light.size(), t = camera.size();
  std::array<MisVertex, kMaxVertices> lv, cv;
  for (std::size_t i = 0; i < s; ++i) lv[i] = {light[i].pdf_fwd, light[i].pdf_rev, light[i].delta};
  for (std::size_t i = 0; i < t; ++i) {
    cv[i] = {camera[i].pdf_fwd, camera[i].pdf_rev, camera[i].delta};
  }
  const PathVertex* qs = s > 0 ? &light[s - 1] : nullptr;
  const PathVertex* pt = t > 0 ? &camera[t - 1] : nullptr;
  const PathVertex* qs_minus = s > 1 ? &light[s - 2] : nullptr;
  const PathVertex* pt_minus = t > 1 ? &camera[t - 2] : nullptr;

  // The four densities a connection changes: of each end vertex sampled from the other side,
  // and of each end's predecessor sampled through the connection.
  if (t > 0) {
    cv[t - 1].delta = false;
    cv[t - 1].pdf_rev =
        s > 0 ? pdf_area_towards(scene, *qs, qs_minus, *pt) : emitter_position_pdf(scene, *pt);
  }
  if (pt_minus) {
    cv[t - 2].pdf_rev = s > 0 ? pdf_area_towards(scene, *pt, qs, *pt_minus)
                              : emission_pdf_towards(scene, *pt, *pt_minus);
  }
  if (s > 0) {
    lv[s - 1].delta = false;
    lv[s - 1].pdf_rev = pdf_area_towards(scene, *pt, pt_minus, *qs);
  }
  if (qs_minus) lv[s - 2].pdf_rev = pdf_area_towards(scene, *qs, pt, *qs_minus);

  const double own = counts.count(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(t));
  double others = 0.0;
  double ratio = 1.0;
  for (std::size_t i = t - 1; i > 0; --i) {  // moving the join towards the camera
    ratio *= remap0(cv[i].pdf_rev) / remap0(cv[i].pdf_fwd);
    if (!cv[i].delta && !cv[i - 1].delta) {
      others += ratio *
                counts.count(static_cast<std::uint32_t>(s + t - i), static_cast<std::uint32_t>(i)) /
                own;
    }
  }
  ratio = 1.0;
  const bool point_light = s > 0 && light[0].point_light;
  for (std::size_t i = s; i-- > 0;) {  // moving the join towards the emitter
    ratio *= remap0(lv[i].pdf_rev) / remap0(lv[i].pdf_fwd);
    const bool before_delta = i > 0 ? lv[i - 1].delta : point_light;
    if (!lv[i].delta && !before_delta) {
      others += ratio *
                counts.count(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(s + t - i)) /
                own;
    }
  }
  return 1.0 / (1.0 + others);
}

Rgb connect(const Scene& scene, std::span<const PathVertex> light,
            std::span<const PathVertex> camera, const StrategyCounts& counts,
            const ConnectOptions& options, TraceCounters& counters,
            std::optional<PixelPosition>* pixel) {
  const std::size_t s = light.size(), t = camera.size();
  if (counts.count(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(t)) <= 0.0) {
    return {};
  }
  Rgb value;
  if (s == 0) {  // the camera subpath found an emitter by itself
    const PathVertex& pt = camera[t - 1];
    if (pt.kind != VertexKind::kSurface) return {};
    const Triangle& tri = scene.triangle(pt.triangle);
    if (tri.emission.is_black() || dot(pt.normal, pt.to_previous) <= 0.0) return {};
    value = pt.beta * tri.emission;
  } else {
    const PathVertex& qs = light[s - 1];
    const PathVertex& pt = camera[t - 1];
    if (qs.delta || pt.delta) return {};
    ++counters.connections;
    const Vec3 d = pt.position - qs.position;
    const double distance_squared = dot(d, d);
    if (distance_squared == 0.0) return {};
    const Vec3 w = d / std::sqrt(distance_squared);  // from the light side to the camera side
    if (t == 1) {
      const auto where = scene.camera().project(-w);
      if (pixel) *pixel = where;
      if (!where) return {};
      value = qs.beta * scattering(scene, qs, pt.position) *
              (abs_cos_at(qs, w) / distance_squared * scene.camera().pixel_pdf(where->cos_theta));
    } else {
      const Rgb f_camera = bsdf_eval(scene.material(pt.triangle), pt.normal, pt.to_previous, -w);
      value = qs.beta * scattering(scene, qs, pt.position) * f_camera * pt.beta *
              (abs_cos_at(qs, w) * abs_cos_at(pt, w) / distance_squared);
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
        if (scene.occluded(qs.position, pt.position)) {
          ++counters.occluded;
          return {};
        }
      }
    }
  }
  if (!options.weighted) return value;
  return value * mis_weight(scene, light, camera, counts);
}

}  // namespace pcbench::scene

#include "integrands/scenes/emitters.h"

#include <algorithm>
#include <cmath>

#include "base/lane_select.h"

namespace pcbench::scene {
namespace {

// A uniform point of the unit square folded onto the triangle a, b >= 0, a + b <= 1 (the half
// past the diagonal reflected through it), by selects: the fold is a coin flip, which as a
// branch was mispredicted half the time, and selects let sample_many's loop run in lanes.
struct Folded {
  double a, b;
};
Folded fold_unit_square(double u1, double u2) {
  const bool fold = u1 + u2 > 1.0;
  return {lane_select(fold, 1.0 - u1, u1), lane_select(fold, 1.0 - u2, u2)};
}

}  // namespace

double triangle_area(const Triangle& t) {
  return 0.5 * length(cross(t.p1 - t.p0, t.p2 - t.p0));
}
Vec3 triangle_normal(const Triangle& t) {
  return normalize(cross(t.p1 - t.p0, t.p2 - t.p0));
}

Emitters::Emitters(const SceneDescription& scene)
    : triangle_pdf_area_(scene.triangles.size(), 0.0) {
  double total = 0.0;
  for (std::uint32_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    if (t.emission.is_black()) continue;
    const double power = kPi * triangle_area(t) * t.emission.average();
    entries_.push_back({.p0 = t.p0,
                        .edge1 = t.p1 - t.p0,
                        .edge2 = t.p2 - t.p0,
                        .normal = triangle_normal(t),
                        .radiance = t.emission,
                        .probability = power,
                        .pdf_area = 0.0,
                        .point_light = false,
                        .index = i});
    total += power;
  }
  for (std::uint32_t i = 0; i < scene.point_lights.size(); ++i) {
    const PointLight& light = scene.point_lights[i];
    if (light.intensity.is_black()) continue;
    const double power = 4.0 * kPi * light.intensity.average();
    entries_.push_back({.p0 = light.position,
                        .edge1 = {},
                        .edge2 = {},
                        .normal = {},
                        .radiance = light.intensity,
                        .probability = power,
                        .pdf_area = 0.0,
                        .point_light = true,
                        .index = i});
    total += power;
    ++point_light_count_;
  }
  for (Entry& e : entries_) {
    e.probability /= total;
    if (e.point_light) {
      e.pdf_area = e.probability;  // a delta: the probability of the light itself
    } else {
      e.pdf_area = e.probability / triangle_area(scene.triangles[e.index]);
      triangle_pdf_area_[e.index] = e.pdf_area;
    }
  }
  choice_.build(probabilities(), DiscreteSamplerKind::kAlias);
}

std::uint32_t Emitters::entry_for(double u_select) const {
  return choice_.pick(u_select);
}

std::vector<double> Emitters::probabilities() const {
  std::vector<double> p;
  for (const Entry& e : entries_) p.push_back(e.probability);
  return p;
}

std::vector<double> Emitters::choice_probabilities() const {
  return choice_.alias_probabilities();
}

double Emitters::pdf_area(std::uint32_t triangle) const {
  return triangle_pdf_area_[triangle];
}

EmitterPoint Emitters::point_on(const Entry& e, double u1, double u2) {
  // Every member given: a default-built point was zeroed first (rep stos), then filled.
  if (e.point_light) {
    return {.position = e.p0,
            .normal = {},
            .radiance = e.radiance,
            .pdf_area = e.pdf_area,
            .point_light = true,
            .index = e.index};
  }
  const auto [a, b] = fold_unit_square(u1, u2);
  return {.position = e.p0 + a * e.edge1 + b * e.edge2,
          .normal = e.normal,
          .radiance = e.radiance,
          .pdf_area = e.pdf_area,
          .point_light = false,
          .index = e.index};
}

EmitterPoint Emitters::sample(double u_select, double u1, double u2) const {
  return point_on(entries_[entry_for(u_select)], u1, u2);
}

void Emitters::sample_many(std::span<const double> u, EmitterPoints& out) const {
  out.size = u.size() / 3;
  // The entries first, then the points: the choices are independent of each other, and apart
  // from the rows they load the loops overlap them. point_on's arithmetic without its branch on
  // a point light, whose row has no edges and whose position is taken as it is.
  std::uint32_t chosen[EmitterPoints::kCapacity];
  for (std::size_t j = 0; j < out.size; ++j) chosen[j] = entry_for(u[3 * j]);
  for (std::size_t j = 0; j < out.size; ++j) {
    const Entry& e = entries_[chosen[j]];
    const auto [a, b] = fold_unit_square(u[3 * j + 1], u[3 * j + 2]);
    out.x[j] = lane_select(e.point_light, e.p0.x, e.p0.x + a * e.edge1.x + b * e.edge2.x);
    out.y[j] = lane_select(e.point_light, e.p0.y, e.p0.y + a * e.edge1.y + b * e.edge2.y);
    out.z[j] = lane_select(e.point_light, e.p0.z, e.p0.z + a * e.edge1.z + b * e.edge2.z);
    out.normal_x[j] = e.normal.x;
    out.normal_y[j] = e.normal.y;
    out.normal_z[j] = e.normal.z;
    out.red[j] = e.radiance.r;
    out.green[j] = e.radiance.g;
    out.blue[j] = e.radiance.b;
    out.pdf_area[j] = e.pdf_area;
    out.point_light[j] = e.point_light ? 1.0 : 0.0;
    out.index[j] = e.index;
  }
}

}  // namespace pcbench::scene

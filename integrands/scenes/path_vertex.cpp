#include "integrands/scenes/path_vertex.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "integrands/scenes/bsdf.h"
#include "integrands/scenes/turn_trig.h"

namespace pcbench::scene {
namespace {

// Continues a subpath from its last vertex by BSDF sampling until it has `walk.max_vertices`
// vertices, leaves the scene, or a sample is invalid, one ray at a time.
void random_walk(const Scene& scene, RandomStream& rng, Walk& walk, std::vector<PathVertex>& path,
                 std::uint64_t& rays) {
  while (path.size() < walk.max_vertices) {
    Hit hit;
    ++rays;
    if (!scene.intersect(path.back().position, walk.direction, hit)) return;
    if (!walk_step(scene, rng, hit, path, walk)) return;
  }
}

// The segment's length is the hit distance: the area conversions need no square root.
double inv_distance_squared(const Hit& hit) {
  return 1.0 / (hit.distance * hit.distance);
}

}  // namespace

bool walk_step(const Scene& scene, RandomStream& rng, const Hit& hit, std::vector<PathVertex>& path,
               Walk& walk) {
  if (!walk_arrive(scene, hit, path, walk)) return false;
  const double u1 = rng.uniform(), u2 = rng.uniform();
  return walk_scatter(scene, hit, u1, cos_sin_of_turn(u2), path, walk);
}

bool walk_arrive(const Scene& scene, const Hit& hit, std::vector<PathVertex>& path,
                 const Walk& walk) {
  const PathVertex& previous = path.back();
  const Vec3 direction = walk.direction;
  const Vec3& normal = scene.normal(hit.triangle);
  const double pdf_fwd =
      walk.previous_delta
          ? 0.0
          : walk.direction_pdf * std::abs(dot(normal, direction)) * inv_distance_squared(hit);
  // Every member given, so nothing is zeroed first (a local vertex zeroed with rep stos and
  // copied in had stalled). Braces, not emplace_back's parentheses: clang 15 (Debian 12's, the
  // asan build) has no parenthesised aggregate initialisation.
  path.emplace_back(PathVertex{VertexKind::kSurface, is_delta(scene.material(hit.triangle)), false,
                               hit.triangle, previous.position + hit.distance * direction, normal,
                               -direction, walk.beta, pdf_fwd, 0.0,
                               std::numeric_limits<double>::quiet_NaN()});
  return path.size() != walk.max_vertices;
}

bool walk_scatter(const Scene& scene, const Hit& hit, double u1, CosSin azimuth,
                  std::vector<PathVertex>& path, Walk& walk) {
  PathVertex& current = path.back();
  const Material& material = scene.material(hit.triangle);
  const BsdfSample s = bsdf_sample(material, current.normal, current.to_previous, u1, azimuth);
  if (!s.valid) return false;
  walk.beta = walk.beta * s.f * (std::abs(dot(s.wi, current.normal)) / s.pdf);
  if (walk.beta.is_black()) return false;
  // The density of walking back from the next vertex to the previous one, at the previous.
  PathVertex& before = path[path.size() - 2];
  before.pdf_rev = s.delta
                       ? 0.0
                       : bsdf_pdf(material, current.normal, s.wi, current.to_previous) *
                             abs_cos_at(before, current.to_previous) * inv_distance_squared(hit);
  walk.direction = s.wi;
  walk.direction_pdf = s.pdf;
  walk.previous_delta = s.delta;
  return true;
}

Rgb emitted_towards(const Scene& scene, const PathVertex& v, const Vec3& direction) {
  if (v.point_light) return scene.description().point_lights[v.triangle].intensity;
  const Triangle& t = scene.triangle(v.triangle);
  return dot(v.normal, direction) > 0.0 ? t.emission : Rgb{};
}

double emission_pdf(const PathVertex& v, const Vec3& w) {
  if (v.point_light) return 1.0 / (4.0 * kPi);
  const double c = dot(v.normal, w);
  return c > 0.0 ? c * kInvPi : 0.0;
}

Walk start_camera_path(const Scene& scene, double fx, double fy, std::uint32_t max_length,
                       std::vector<PathVertex>& path) {
  path.clear();
  // A fresh vector: one allocation, not one per doubling.
  path.reserve(std::size_t{max_length} + 1);
  const CameraModel& camera = scene.camera();
  PathVertex y0;
  y0.kind = VertexKind::kCamera;
  y0.position = camera.position();
  y0.beta = {1.0, 1.0, 1.0};
  path.push_back(y0);
  const Vec3 direction = camera.direction(fx, fy);
  return {.direction = direction,
          .direction_pdf = camera.pixel_pdf(camera.cos_theta(direction)),
          .beta = {1.0, 1.0, 1.0},
          .max_vertices = std::size_t{max_length} + 1};
}

void trace_camera_path(const Scene& scene, double fx, double fy, RandomStream& rng,
                       std::uint32_t max_length, std::vector<PathVertex>& path,
                       TraceCounters& counters) {
  Walk walk = start_camera_path(scene, fx, fy, max_length, path);
  random_walk(scene, rng, walk, path, counters.camera_rays);
}

PathVertex sample_emitter_vertex(const Scene& scene, RandomStream& rng) {
  const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
  return emitter_vertex(scene.emitters().sample(u0, u1, u2));
}

PathVertex emitter_vertex(const EmitterPoint& e) {
  // Every member given: a default-built vertex was zeroed first (rep stos), then filled.
  return {.kind = VertexKind::kEmitter,
          .delta = false,
          .point_light = e.point_light,
          .triangle = e.index,
          .position = e.position,
          .normal = e.normal,
          .to_previous = {},
          .beta = Rgb{1.0, 1.0, 1.0} / e.pdf_area,
          .pdf_fwd = e.pdf_area,
          .pdf_rev = 0.0,
          .weight_sum = std::numeric_limits<double>::quiet_NaN()};
}

EmitterPoint emitter_point(const Scene& scene, const PathVertex& v) {
  return {.position = v.position,
          .normal = v.normal,
          .radiance = v.point_light ? scene.description().point_lights[v.triangle].intensity
                                    : scene.triangle(v.triangle).emission,
          .pdf_area = v.pdf_fwd,
          .point_light = v.point_light,
          .index = v.triangle};
}

std::optional<Walk> start_light_path(const Scene& scene, RandomStream& rng,
                                     std::uint32_t max_length, std::vector<PathVertex>& path,
                                     TraceCounters& counters) {
  path.clear();
  path.reserve(std::max<std::size_t>(max_length, 1));  // as in start_camera_path
  ++counters.light_paths;
  path.push_back(sample_emitter_vertex(scene, rng));
  if (max_length < 2) return std::nullopt;
  const PathVertex& x0 = path.back();
  const double u1 = rng.uniform(), u2 = rng.uniform();
  Vec3 direction;
  double pdf = 0.0;
  if (x0.point_light) {
    const double z = 1.0 - 2.0 * u1;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const CosSin phi = cos_sin_of_turn(u2);
    direction = {r * phi.cos, r * phi.sin, z};
    pdf = 1.0 / (4.0 * kPi);
  } else {
    direction = sample_cosine_hemisphere(x0.normal, u1, u2);
    pdf = dot(direction, x0.normal) * kInvPi;
    if (!(pdf > 0.0)) return std::nullopt;
  }
  const Rgb radiance = emitted_towards(scene, x0, direction);
  const Rgb beta = x0.beta * radiance * (abs_cos_at(x0, direction) / pdf);
  return Walk{
      .direction = direction, .direction_pdf = pdf, .beta = beta, .max_vertices = max_length};
}

void trace_light_path(const Scene& scene, RandomStream& rng, std::uint32_t max_length,
                      std::vector<PathVertex>& path, TraceCounters& counters) {
  std::optional<Walk> walk = start_light_path(scene, rng, max_length, path, counters);
  if (walk) random_walk(scene, rng, *walk, path, counters.light_rays);
}

}  // namespace pcbench::scene

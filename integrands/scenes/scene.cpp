#include "integrands/scenes/scene.h"

#include "integrands/scenes/embree_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pcbench::scene {
namespace {

// Largest triangle count for which convexity is checked (the check is quadratic).
constexpr std::size_t kConvexityCheckMax = 4096;

double bounding_diagonal(const SceneDescription& d) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  auto grow = [&](const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  for (const Triangle& t : d.triangles) {
    grow(t.p0);
    grow(t.p1);
    grow(t.p2);
  }
  grow(d.camera.position);
  return length(hi - lo);
}

// True when every vertex, the camera and every point light lie on the front side of every
// triangle's plane: the triangles bound one convex region seen from inside.
bool convex_enclosure(const SceneDescription& d, const std::vector<Vec3>& normals,
                      double tolerance) {
  if (d.triangles.empty() || d.triangles.size() > kConvexityCheckMax) return false;
  for (std::size_t i = 0; i < d.triangles.size(); ++i) {
    const Vec3& p = d.triangles[i].p0;
    const Vec3& n = normals[i];
    auto behind = [&](const Vec3& q) { return dot(q - p, n) < -tolerance; };
    if (dot(d.camera.position - p, n) <= tolerance) return false;
    for (const PointLight& l : d.point_lights) {
      if (behind(l.position)) return false;
    }
    for (const Triangle& t : d.triangles) {
      if (behind(t.p0) || behind(t.p1) || behind(t.p2)) return false;
    }
  }
  return true;
}

void log_ray(const RTCRay& ray, bool occlusion, std::vector<LoggedRay>& log) {
  log.push_back({.origin = {ray.org_x, ray.org_y, ray.org_z},
                 .direction = {ray.dir_x, ray.dir_y, ray.dir_z},
                 .tnear = ray.tnear,
                 .tfar = ray.tfar,
                 .occlusion = occlusion});
}

}  // namespace

bool is_convex_enclosure(const SceneDescription& d) {
  std::vector<Vec3> normals;
  for (const Triangle& t : d.triangles) normals.push_back(triangle_normal(t));
  return convex_enclosure(d, normals, 1e-9 * bounding_diagonal(d));
}

Scene::Scene(SceneDescription description)
    : description_(std::move(description)),
      camera_(description_.camera, description_.width, description_.height),
      embree_(std::make_unique<EmbreeScene>(description_.triangles)) {
  for (const Triangle& t : description_.triangles) normals_.push_back(triangle_normal(t));
  emitters_ = std::make_unique<Emitters>(description_);
  const double diagonal = bounding_diagonal(description_);
  epsilon_ = 1e-5 * diagonal;

  traits_.convex_enclosure = convex_enclosure(description_, normals_, 1e-9 * diagonal);
  for (const Material& m : description_.materials) {
    traits_.has_glossy |= m.kind == MaterialKind::kPhong;
    traits_.has_specular |= m.kind == MaterialKind::kMirror;
  }
  traits_.has_point_lights = emitters_->has_point_lights();
  packet_width_ = embree_->native_packet_width();
}

Scene::~Scene() = default;

bool Scene::intersect(const Vec3& origin, const Vec3& direction, Hit& hit,
                      double max_distance) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  fill_ray(rh.ray, origin, direction, static_cast<float>(epsilon_),
           static_cast<float>(std::min(max_distance, 1e30)));
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  if (ray_log_ != nullptr) [[unlikely]]
    log_ray(rh.ray, false, *ray_log_);
  rtcIntersect1(embree_->handle(), &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit = hit_of(rh.hit.primID, rh.ray.tfar, origin, direction);
  return true;
}

Hit Scene::hit_of(std::uint32_t primitive, float tfar, const Vec3& origin,
                  const Vec3& direction) const {
  Hit hit;
  hit.triangle = primitive;
  // The distance is recomputed in double against the triangle's plane, so that the hit point
  // lies on the triangle to double precision (float tfar would put it off the surface).
  const Triangle& t = description_.triangles[hit.triangle];
  const Vec3& n = normals_[hit.triangle];
  const double denominator = dot(direction, n);
  hit.distance = denominator != 0.0 ? dot(t.p0 - origin, n) / denominator : tfar;
  if (!(hit.distance > 0.0)) hit.distance = tfar;
  return hit;
}

bool Scene::occluded(const ShadowRay& shadow) const {
  if (shadow.empty) return false;
  // The ray runs along d itself (Embree takes unnormalised directions), so t is the fraction of
  // the segment, both ends excluded by epsilon: the direction needs no division, and its
  // conversion need not wait for the square root.
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  fill_ray(ray, shadow.origin, shadow.d, static_cast<float>(shadow.margin),
           static_cast<float>(1.0 - shadow.margin));
  if (ray_log_ != nullptr) [[unlikely]]
    log_ray(ray, true, *ray_log_);
  rtcOccluded1(embree_->handle(), &context, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();
}

}  // namespace pcbench::scene

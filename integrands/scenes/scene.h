// A scene ready to trace: its description, the Embree BVH (built once, shared read-only by every
// thread and every run of the scene), the emitters, the camera, and what the geometry and the
// materials let the estimators skip.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "integrands/scenes/camera_model.h"
#include "integrands/scenes/emitters.h"
#include "integrands/scenes/scene_description.h"

namespace pcbench::scene {

class EmbreeScene;

struct Hit {
  double distance = 0.0;
  std::uint32_t triangle = 0;
};

// One ray as Embree was given it, for measurement: benchmarks/bench_ray_rate.cpp replays a run's
// own rays through Embree alone to measure the share of a run's time its other work takes.
struct LoggedRay {
  float origin[3];
  float direction[3];
  float tnear, tfar;
  bool occlusion;  // rtcOccluded1 (a shadow ray), else rtcIntersect1
};

// What the scene does not need, inferred from geometry and materials (never from its name).
struct SceneTraits {
  // Every triangle faces into one convex enclosure that holds the camera and the point lights:
  // two points of the scene always see each other, so connections need no shadow ray.
  bool convex_enclosure = false;
  bool has_glossy = false;    // any Phong material
  bool has_specular = false;  // any mirror
  bool has_point_lights = false;
};

// Whether the triangles bound one convex region that holds the camera and the point lights
// (SceneTraits::convex_enclosure).
bool is_convex_enclosure(const SceneDescription& description);

class Scene {
 public:
  explicit Scene(SceneDescription description);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  const SceneDescription& description() const { return description_; }
  const SceneTraits& traits() const { return traits_; }
  const Emitters& emitters() const { return *emitters_; }
  const CameraModel& camera() const { return camera_; }
  const Triangle& triangle(std::uint32_t i) const { return description_.triangles[i]; }
  const Material& material(std::uint32_t triangle) const {
    return description_.materials[description_.triangles[triangle].material];
  }
  const Vec3& normal(std::uint32_t triangle) const { return normals_[triangle]; }

  // The closest hit along origin + t·direction for t in (epsilon, max_distance).
  bool intersect(const Vec3& origin, const Vec3& direction, Hit& hit,
                 double max_distance = 1e30) const;
  // Whether anything lies strictly between a and b (both ends excluded by epsilon).
  bool occluded(const Vec3& a, const Vec3& b) const { return occluded(shadow_ray(a, b)); }

  // A shadow ray from a to b = a + d, set up apart from tracing it so that a caller that has the
  // segment's length already (connect) shares it, and the margin's division runs while the
  // caller does other work instead of just before Embree waits for it.
  struct ShadowRay {
    Vec3 origin, d;
    double margin = 0.0;  // epsilon / |d|: the fraction of d left out at each end
    bool empty = true;    // the ends are within 2 epsilon: nothing lies between them
  };
  // `distance` = sqrt(distance_squared) = |b - a|.
  ShadowRay shadow_ray(const Vec3& a, const Vec3& b, double distance_squared,
                       double distance) const {
    if (distance_squared <= 4.0 * epsilon_ * epsilon_) return {a, b - a, 0.0, true};
    return {a, b - a, epsilon_ / distance, false};
  }
  ShadowRay shadow_ray(const Vec3& a, const Vec3& b) const {
    const Vec3 d = b - a;
    const double distance_squared = dot(d, d);
    return shadow_ray(a, b, distance_squared, std::sqrt(distance_squared));
  }
  bool occluded(const ShadowRay& ray) const;

  // Many rays at once, in Embree packets of packet_width() (a partial last packet masked): the
  // same hits and the same answers as intersect() and occluded() ray by ray, for callers that
  // keep many paths in lanes (path_lanes.h). `origins`, `directions` and `hits` are parallel;
  // found[i] says whether ray i hit.
  void intersect_many(std::span<const Vec3> origins, std::span<const Vec3> directions,
                      std::span<Hit> hits, std::span<std::uint8_t> found) const;
  void occluded_many(std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked) const;
  // Rays per Embree packet: 16, 8 or 4, the widest the machine and Embree's build trace natively.
  std::uint32_t packet_width() const { return packet_width_; }

  // Distances below this count as self-intersections: a small fraction of the scene's size.
  double epsilon() const { return epsilon_; }

  // Measurement only: while a log is set, intersect and occluded append every ray they trace
  // (null stops). Not thread-safe: set it only while one thread renders. Logging costs a
  // predictable branch per ray when off and changes no result.
  void log_rays(std::vector<LoggedRay>* log) const { ray_log_ = log; }

 private:
  SceneDescription description_;
  std::vector<Vec3> normals_;
  std::unique_ptr<Emitters> emitters_;
  CameraModel camera_;
  SceneTraits traits_;
  double epsilon_ = 1e-4;
  std::unique_ptr<EmbreeScene> embree_;
  mutable std::vector<LoggedRay>* ray_log_ = nullptr;
  std::uint32_t packet_width_ = 4;

  // The hit of an Embree closest-hit answer (`primitive`, `tfar`) for the ray it was given.
  Hit hit_of(std::uint32_t primitive, float tfar, const Vec3& origin, const Vec3& direction) const;
  // intersect_many and occluded_many at one packet width (scene_packets.cpp).
  template <std::uint32_t W>
  void intersect_packets(std::span<const Vec3> origins, std::span<const Vec3> directions,
                         std::span<Hit> hits, std::span<std::uint8_t> found) const;
  template <std::uint32_t W>
  void occluded_packets(std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked) const;
};

}  // namespace pcbench::scene

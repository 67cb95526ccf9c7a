// Sampling where light paths start: an emitter chosen in proportion to its power (area
// triangles: π · area · mean radiance, one-sided; point lights: 4π · mean intensity), a point
// uniform on a triangle, and a direction (cosine-weighted into the front hemisphere of a
// triangle, uniform on the sphere for a point light).
#pragma once

#include <cstdint>
#include <vector>

#include "integrands/scenes/scene_description.h"
#include "integrands/scenes/scene_math.h"

namespace pcbench::scene {

struct EmitterPoint {
  Vec3 position = {};
  Vec3 normal = {};       // zero for a point light
  Rgb radiance = {};      // emitted radiance (area) or intensity (point light)
  double pdf_area = 0.0;  // P(emitter) / area; P(emitter) for a point light (a delta)
  bool point_light = false;
  std::uint32_t index = 0;  // the triangle, or the point light
};

class Emitters {
 public:
  explicit Emitters(const SceneDescription& scene);

  bool empty() const { return cdf_.empty(); }
  bool has_point_lights() const { return point_light_count_ > 0; }

  // A start point from three uniforms.
  EmitterPoint sample(double u_select, double u1, double u2) const;

  // Density (area measure) of sample() producing a point on emitting triangle `triangle`.
  double pdf_area(std::uint32_t triangle) const;

 private:
  struct Entry {
    bool point_light = false;
    std::uint32_t index = 0;  // triangle or point light
    double probability = 0.0;
    Vec3 normal = {};  // the triangle's, computed once (zero for a point light)
  };
  // The entry u_select picks: the first whose cdf exceeds it, as std::upper_bound over the whole
  // cdf finds it, searched within the guide table's bucket of u_select (a few entries, where a
  // search of all of them mispredicts a branch per level).
  std::size_t entry_for(double u_select) const;

  const SceneDescription& scene_;
  std::vector<Entry> entries_;
  std::vector<double> cdf_;
  // guide_[b]: the first entry whose cdf exceeds b / G, for b = 0 .. G (G = guide_.size() - 1).
  std::vector<std::uint32_t> guide_;
  std::vector<double> triangle_pdf_area_;  // per triangle, 0 for a non-emitter
  std::uint32_t point_light_count_ = 0;
};

double triangle_area(const Triangle& t);
Vec3 triangle_normal(const Triangle& t);  // unit, from the winding

}  // namespace pcbench::scene

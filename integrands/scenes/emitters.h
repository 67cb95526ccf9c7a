// Sampling where light paths start: an emitter chosen in proportion to its power (area
// triangles: π · area · mean radiance, one-sided; point lights: 4π · mean intensity), a point
// uniform on a triangle, and a direction (cosine-weighted into the front hemisphere of a
// triangle, uniform on the sphere for a point light).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "base/discrete_sampler.h"
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

// Emitter points in structure-of-arrays form: a batch of resampling candidates, laid out so
// that NextEventValues::values weighs them in SIMD lanes. No member is initialised: a batch is
// filled by Emitters::sample_many, and zeroing a local one first cost more than its arithmetic.
struct EmitterPoints {
  static constexpr std::size_t kCapacity = 64;
  std::size_t size;
  double x[kCapacity], y[kCapacity], z[kCapacity];  // position
  double normal_x[kCapacity], normal_y[kCapacity], normal_z[kCapacity];
  double red[kCapacity], green[kCapacity], blue[kCapacity];  // radiance or intensity
  double pdf_area[kCapacity];
  double point_light[kCapacity];  // 1 or 0: a double, so the lanes select on it without a cast
  std::uint32_t index[kCapacity];

  void set(std::size_t j, const EmitterPoint& p) {
    x[j] = p.position.x;
    y[j] = p.position.y;
    z[j] = p.position.z;
    normal_x[j] = p.normal.x;
    normal_y[j] = p.normal.y;
    normal_z[j] = p.normal.z;
    red[j] = p.radiance.r;
    green[j] = p.radiance.g;
    blue[j] = p.radiance.b;
    pdf_area[j] = p.pdf_area;
    point_light[j] = p.point_light ? 1.0 : 0.0;
    index[j] = p.index;
  }
  EmitterPoint operator[](std::size_t j) const {
    return {.position = {x[j], y[j], z[j]},
            .normal = {normal_x[j], normal_y[j], normal_z[j]},
            .radiance = {red[j], green[j], blue[j]},
            .pdf_area = pdf_area[j],
            .point_light = point_light[j] != 0.0,
            .index = index[j]};
  }
};

class Emitters {
 public:
  explicit Emitters(const SceneDescription& scene);

  bool empty() const { return entries_.empty(); }
  bool has_point_lights() const { return point_light_count_ > 0; }

  // A start point from three uniforms.
  EmitterPoint sample(double u_select, double u1, double u2) const;
  // sample() for u.size() / 3 points (at most EmitterPoints::kCapacity), point j from
  // u[3j], u[3j + 1], u[3j + 2]: the same points.
  void sample_many(std::span<const double> u, EmitterPoints& out) const;

  // Density (area measure) of sample() producing a point on emitting triangle `triangle`.
  double pdf_area(std::uint32_t triangle) const;

 private:
  // One emitter, everything a point on it needs in one row, so that a batch of candidates
  // gathers a row each (sample_many).
  struct Entry {
    Vec3 p0, edge1, edge2;  // a triangle's p0, p1 - p0, p2 - p0; a point light's position, 0, 0
    Vec3 normal;            // the triangle's, computed once (zero for a point light)
    Rgb radiance;           // emitted radiance, or a point light's intensity
    double probability;     // of choosing this emitter
    double pdf_area;        // EmitterPoint::pdf_area
    bool point_light;
    std::uint32_t index;  // triangle or point light
  };
  // The point a row and two uniforms give (sample's arithmetic, one point at a time).
  static EmitterPoint point_on(const Entry& e, double u1, double u2);

 public:
  // The entry u_select picks, by Walker's alias method (Vose's construction): bucket ⌊u n⌋ of n,
  // and within it the entry itself below the bucket's threshold, its alias above. One row read
  // whatever the number of emitters: a search of the cdf waited on a chain of dependent loads, a
  // fifth of a resampling candidate's time (docs/findings/candidates.md). Public for its test.
  std::uint32_t entry_for(double u_select) const;
  // Each entry's probability, ∝ its power (what pdf_area divides), and the probability with
  // which entry_for picks it, from the table (its test holds the two equal).
  std::vector<double> probabilities() const;
  std::vector<double> choice_probabilities() const;

 private:
  std::vector<Entry> entries_;
  DiscreteSampler choice_;                 // an alias table over entries_, ∝ power
  std::vector<double> triangle_pdf_area_;  // per triangle, 0 for a non-emitter
  std::uint32_t point_light_count_ = 0;
};

double triangle_area(const Triangle& t);
Vec3 triangle_normal(const Triangle& t);  // unit, from the winding

}  // namespace pcbench::scene

// pcbpt's light importance (pcbpt.cpp) of every candidate light vertex x_i at one cache point y,
//     q(i) = max channel of β(x_i) f(x_i → y) |cos at x_i| |cos at y| / d²,
// the light subpath's contribution towards y without y's BSDF (0 for a specular x_i), in SIMD
// lanes. A table's cache point weighs every candidate of its iteration, hundreds to thousands of
// them: one at a time, each read its vertex from the pool and evaluated its BSDF through a
// switch, a quarter of the published design's run (docs/findings/lanes.md, session 27).
//
// What does not depend on y is taken once per iteration (assign): the position, the normal
// whose side the light leaves by, and the largest channel of β f, which for a Lambertian surface,
// a triangle emitter and a point light is the same in every direction on that side. A candidate
// whose f depends on the direction (a Phong surface) is weighed by light_importance() itself.
// The lanes keep light_importance()'s order of operations and use no fused multiply-add (the file
// is built without contraction: CMakeLists.txt), so q is light_importance()'s to the bit;
// tests/light_importance_lanes_test.cpp checks it on every built-in scene.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "integrands/scenes/render_services.h"

namespace pcbench::scene {

// q(i) for one candidate x at y, one at a time: the definition the lanes follow.
double light_importance(const Scene& scene, const PathVertex& x, const PathVertex& y);

// Per candidate at one cache point: q, and the segment's squared length and length, from which
// the candidate's shadow ray is set up as Scene::shadow_ray(x, y) would (the same numbers).
struct LightImportances {
  std::vector<double> q, distance_squared, distance;
};

class LightImportanceLanes {
 public:
  // The candidates of an iteration: the last vertex of each light prefix `vertices` names.
  void assign(const Scene& scene, const LightPool& pool, std::span<const LightVertexRef> vertices);

  std::size_t size() const { return x_.size(); }
  Vec3 position(std::size_t i) const { return {x_[i], y_[i], z_[i]}; }

  // light_importance(scene, x_i, y) of every candidate into out.q[0 .. size()), with each
  // segment's squared length and length; out's vectors are resized to size().
  void at(const Scene& scene, const PathVertex& y, LightImportances& out) const;

 private:
  std::vector<double> x_, y_, z_;     // position
  std::vector<double> nx_, ny_, nz_;  // the normal on whose side f is nonzero (0 at a point light)
  std::vector<double> weight_;        // max channel of β f on that side (0 for a specular vertex)
  std::vector<double> point_light_;   // 1 or 0: |cos| is 1 and every side is lit
  std::vector<double> lanes_;         // 1 where the lanes weigh it, 0 where q is set otherwise
  // Candidates whose f depends on the direction (Phong), weighed one at a time.
  std::vector<std::uint32_t> directional_;
  std::vector<const PathVertex*> directional_vertex_;
};

}  // namespace pcbench::scene

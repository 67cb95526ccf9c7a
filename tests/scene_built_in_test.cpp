// The built-in scenes' geometry: every name builds, has a registry entry and is a closed room
// (no camera ray, nor any ray from the camera, escapes), and many-lights is what it is for: many
// emitters of very different power, most of whose power is hidden from the floor the camera sees
// (so that next-event estimation choosing lights by power mostly traces occluded shadow rays).
//
// No randomness: directions and uniforms come from fixed low-discrepancy sequences.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/emitters.h"
#include "integrands/scenes/scene.h"
#include "integrands/scenes/scene_integrand.h"

namespace pcbench::scene {
namespace {

// The fractional part of n·step (an additive recurrence: well spread in [0, 1)).
double sequence(std::uint64_t n, double step) {
  const double v = static_cast<double>(n) * step;
  return v - std::floor(v);
}
constexpr double kGolden = 0.6180339887498949;
constexpr double kPlastic1 = 0.7548776662466927, kPlastic2 = 0.5698402909980532;

Scene small(const std::string& name, std::uint32_t side) {
  SceneDescription d = *built_in_scene(name);
  d.width = d.height = side;
  return Scene(std::move(d));
}

TEST(SceneBuiltIn, EveryNameBuildsAndIsAnIntegrand) {
  std::set<std::string> entries;
  for (const IntegrandEntry& e : scene_integrand_entries()) entries.insert(e.name);
  EXPECT_EQ(entries.size(), built_in_scene_names().size());
  for (const std::string& name : built_in_scene_names()) {
    const auto d = built_in_scene(name);
    ASSERT_TRUE(d.has_value()) << name;
    EXPECT_EQ(d->name, name);
    EXPECT_EQ(d->source, "built-in");
    EXPECT_TRUE(entries.contains(name)) << name;
  }
  EXPECT_FALSE(built_in_scene("no-such-scene").has_value());
}

TEST(SceneBuiltIn, NoRayFromTheCameraEscapes) {
  for (const std::string& name : built_in_scene_names()) {
    SCOPED_TRACE(name);
    const Scene scene = small(name, 32);
    const CameraModel& camera = scene.camera();
    int escaped = 0;
    // Every pixel's centre and a jittered point in it.
    for (std::uint32_t y = 0; y < camera.height(); ++y) {
      for (std::uint32_t x = 0; x < camera.width(); ++x) {
        const std::uint64_t n = y * camera.width() + x;
        for (const auto& [fx, fy] :
             {std::pair{0.5, 0.5}, std::pair{sequence(n, kPlastic1), sequence(n, kPlastic2)}}) {
          Hit hit;
          escaped += !scene.intersect(camera.position(), camera.direction(x + fx, y + fy), hit);
        }
      }
    }
    // Directions over the whole sphere (a Fibonacci lattice).
    constexpr int kDirections = 20000;
    for (int i = 0; i < kDirections; ++i) {
      const double z = 1.0 - 2.0 * (i + 0.5) / kDirections;
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      const double phi = 2.0 * kPi * sequence(static_cast<std::uint64_t>(i), kGolden);
      Hit hit;
      escaped +=
          !scene.intersect(camera.position(), {r * std::cos(phi), r * std::sin(phi), z}, hit);
    }
    EXPECT_EQ(escaped, 0);
  }
}

TEST(SceneBuiltIn, ManyLightsHasManyEmittersOfVeryDifferentRadiance) {
  const SceneDescription d = *built_in_scene("many-lights");
  EXPECT_TRUE(d.point_lights.empty());
  EXPECT_LE(d.triangles.size(), 400u);
  std::vector<double> radiance;
  for (const Triangle& t : d.triangles) {
    if (t.emission.is_black()) continue;
    radiance.push_back(t.emission.average());
    EXPECT_LT(triangle_normal(t).y, -0.99) << "emitters face down into the room";
  }
  ASSERT_EQ(radiance.size() % 2, 0u);  // quads
  EXPECT_GE(radiance.size() / 2, 64u);
  EXPECT_LE(radiance.size() / 2, 256u);
  const auto [lo, hi] = std::minmax_element(radiance.begin(), radiance.end());
  EXPECT_GE(*hi / *lo, 50.0);
  EXPECT_LE(*hi / *lo, 200.0);
}

// From the floor points the camera sees, the share of next-event samples (an emitter chosen by
// power, a point uniform on it) whose shadow ray is blocked.
double occluded_share_from_the_floor(const std::string& name) {
  const Scene scene = small(name, 32);
  const CameraModel& camera = scene.camera();
  constexpr int kPerPoint = 64;
  std::uint64_t draws = 0, blocked = 0, n = 0;
  for (std::uint32_t y = 0; y < camera.height(); ++y) {
    for (std::uint32_t x = 0; x < camera.width(); ++x) {
      Hit hit;
      const Vec3 direction = camera.direction(x + 0.5, y + 0.5);
      if (!scene.intersect(camera.position(), direction, hit)) continue;
      const Vec3 p = camera.position() + hit.distance * direction;
      if (scene.normal(hit.triangle).y < 0.99 || p.y > 1e-6) continue;  // the floor only
      for (int k = 0; k < kPerPoint; ++k, ++n) {
        const EmitterPoint e = scene.emitters().sample(sequence(n, kGolden), sequence(n, kPlastic1),
                                                       sequence(n, kPlastic2));
        ++draws;
        blocked += scene.occluded(p, e.position);
      }
    }
  }
  EXPECT_GT(draws, 100u * kPerPoint) << "the camera sees the floor";
  return draws == 0 ? 0.0 : static_cast<double>(blocked) / static_cast<double>(draws);
}

TEST(SceneBuiltIn, ManyLightsHidesMostOfItsPowerFromTheFloor) {
  const double share = occluded_share_from_the_floor("many-lights");
  std::printf("many-lights: %.1f%% of next-event samples from the floor are occluded\n",
              100.0 * share);
  EXPECT_GT(share, 0.6);
}

}  // namespace
}  // namespace pcbench::scene

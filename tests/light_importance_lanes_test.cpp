// pcbpt's light importance in SIMD lanes (estimators/scene/light_importance_lanes.h) against
// light_importance() one candidate at a time, on every built-in scene: every vertex of a pool of
// light subpaths (emitter points, point lights, Lambertian, Phong and mirror vertices where the
// scene has them) at every vertex of camera subpaths, the same q to the bit, and each segment's
// length what Scene::shadow_ray(x, y) takes. The tables these make are checked whole by ctest
// estimators.hashes.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "base/rng.h"
#include "estimators/scene/light_importance_lanes.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/render_services.h"
#include "integrands/scenes/scene.h"
#include "test_support.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kPaths = 48;

class LightImportanceLanesOn : public ::testing::TestWithParam<std::string> {};

TEST_P(LightImportanceLanesOn, ImportancesAreLightImportances) {
  SceneDescription description = *built_in_scene(GetParam());
  description.width = description.height = 8;
  const Scene scene(std::move(description));
  TraceCounters setup;
  LightPool pool;
  pool.paths.resize(kPaths);
  for (std::uint32_t p = 0; p < kPaths; ++p) {
    RandomStream rng({.key = 0x11a7, .purpose = StreamPurpose::kLightPool, .path = p});
    trace_light_path(scene, rng, scene.description().max_length, pool.paths[p], setup);
  }
  const std::vector<LightVertexRef> vertices = light_vertices(pool);
  LightImportanceLanes lanes;
  lanes.assign(scene, pool, vertices);
  ASSERT_EQ(lanes.size(), vertices.size());

  LightImportances at;
  std::size_t positive = 0, compared = 0;
  for (std::uint32_t p = 0; p < 16; ++p) {
    RandomStream rng({.key = 0x11a7, .purpose = StreamPurpose::kCameraPath, .path = p});
    std::vector<PathVertex> camera;
    trace_camera_path(scene, (p % 8) + rng.uniform(), (p / 8) * 2 + rng.uniform(), rng,
                      scene.description().max_length, camera, setup);
    // Every camera vertex as the end, y_0 (the camera) included.
    for (const PathVertex& y : camera) {
      lanes.at(scene, y, at);
      ASSERT_EQ(at.q.size(), vertices.size());
      for (std::size_t i = 0; i < vertices.size(); ++i) {
        const PathVertex& x = light_prefix(pool, vertices[i]).back();
        const double want = light_importance(scene, x, y);
        ASSERT_TRUE(bit_identical(at.q[i], want))
            << "candidate " << i << ": " << at.q[i] << " against " << want;
        ASSERT_TRUE(bit_identical(lanes.position(i).x, x.position.x) &&
                    bit_identical(lanes.position(i).y, x.position.y) &&
                    bit_identical(lanes.position(i).z, x.position.z));
        // The shadow ray from the lanes' segment is the one Scene::shadow_ray(x, y) sets up.
        const Scene::ShadowRay mine =
            scene.shadow_ray(lanes.position(i), y.position, at.distance_squared[i], at.distance[i]);
        const Scene::ShadowRay theirs = scene.shadow_ray(x.position, y.position);
        ASSERT_TRUE(mine.empty == theirs.empty && bit_identical(mine.margin, theirs.margin));
        positive += want > 0.0 ? 1 : 0;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_GT(positive, compared / 20);  // the comparison saw importances, not only zeros
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, LightImportanceLanesOn,
                         ::testing::ValuesIn(built_in_scene_names()), scene_test_name);

}  // namespace
}  // namespace pcbench::scene

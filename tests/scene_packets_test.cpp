// Rays in Embree packets and paths in lanes against the one-ray code they stand in for: the same
// hits (triangle and distance, to the bit), the same occlusion answers, and the same subpaths
// (every vertex's every member), on every built-in scene. What the renderer's images owe to
// these is checked whole by ctest estimators.hashes; these name the part that differs.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "base/rng.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/path_lanes.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"
#include "test_support.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kResolution = 24;

Scene built_in(const std::string& name) {
  SceneDescription d = *built_in_scene(name);
  d.width = d.height = kResolution;
  return Scene(std::move(d));
}

StreamId stream_of(std::uint32_t path) {
  return {.key = 0x5eed,
          .replicate = 3,
          .purpose = StreamPurpose::kCameraPath,
          .sample = 7,
          .path = path};
}

// One camera subpath per pixel, one ray at a time (the reference the lanes must reproduce).
std::vector<std::vector<PathVertex>> camera_paths_one_by_one(const Scene& scene) {
  std::vector<std::vector<PathVertex>> paths(kResolution * kResolution);
  TraceCounters counters;
  for (std::uint32_t p = 0; p < paths.size(); ++p) {
    RandomStream rng(stream_of(p));
    const double fx = p % kResolution + rng.uniform(), fy = p / kResolution + rng.uniform();
    trace_camera_path(scene, fx, fy, rng, scene.description().max_length, paths[p], counters);
  }
  return paths;
}

bool same_bits(const PathVertex& a, const PathVertex& b) {
  auto eq = [](const auto& x, const auto& y) { return std::memcmp(&x, &y, sizeof x) == 0; };
  return a.kind == b.kind && eq(a.position, b.position) && eq(a.normal, b.normal) &&
         eq(a.to_previous, b.to_previous) && a.triangle == b.triangle && eq(a.beta, b.beta) &&
         eq(a.pdf_fwd, b.pdf_fwd) && eq(a.pdf_rev, b.pdf_rev) && a.delta == b.delta &&
         a.point_light == b.point_light;
}

class ScenePackets : public ::testing::TestWithParam<std::string> {};

TEST_P(ScenePackets, IntersectManyIsIntersectRayByRay) {
  const Scene scene = built_in(GetParam());
  // Rays from every camera vertex in the direction it was left by, and back towards the camera:
  // the renderer's own mix of coherent and incoherent rays. An odd count leaves a partial packet.
  std::vector<Vec3> origins, directions;
  for (const auto& path : camera_paths_one_by_one(scene)) {
    for (std::size_t i = 1; i < path.size(); ++i) {
      origins.push_back(path[i].position);
      directions.push_back(path[i].to_previous);
      origins.push_back(path[i - 1].position);
      directions.push_back(-path[i].to_previous);
    }
  }
  origins.pop_back();
  directions.pop_back();
  ASSERT_GT(origins.size(), 1000u);
  std::vector<Hit> hits(origins.size());
  std::vector<std::uint8_t> found(origins.size());
  scene.intersect_many(origins, directions, hits, found);
  std::size_t hit_count = 0;
  for (std::size_t i = 0; i < origins.size(); ++i) {
    Hit one;
    const bool expected = scene.intersect(origins[i], directions[i], one);
    ASSERT_EQ(found[i] != 0, expected) << "ray " << i;
    if (!expected) continue;
    ++hit_count;
    EXPECT_EQ(hits[i].triangle, one.triangle) << "ray " << i;
    EXPECT_EQ(std::memcmp(&hits[i].distance, &one.distance, sizeof(double)), 0) << "ray " << i;
  }
  EXPECT_GT(hit_count, origins.size() / 2);
}

TEST_P(ScenePackets, OccludedManyIsOccludedRayByRay) {
  const Scene scene = built_in(GetParam());
  // Shadow rays between the camera paths' vertices and those of the next pixel's path, some of
  // them empty (a vertex with itself).
  const auto paths = camera_paths_one_by_one(scene);
  std::vector<Scene::ShadowRay> rays;
  for (std::size_t p = 0; p + 1 < paths.size(); ++p) {
    for (std::size_t i = 1; i < paths[p].size(); ++i) {
      const Vec3& a = paths[p][i].position;
      const Vec3& b = paths[p + 1][std::min(i, paths[p + 1].size() - 1)].position;
      rays.push_back(scene.shadow_ray(a, b));
      if (i == 1) rays.push_back(scene.shadow_ray(a, a));
    }
  }
  std::vector<std::uint8_t> blocked(rays.size());
  scene.occluded_many(rays, blocked);
  std::size_t blocked_count = 0, empty_count = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(blocked[i] != 0, scene.occluded(rays[i])) << "ray " << i;
    blocked_count += blocked[i];
    empty_count += rays[i].empty;
  }
  EXPECT_GT(empty_count, 0u);
  if (!scene.traits().convex_enclosure) {
    EXPECT_GT(blocked_count, 0u);
  }
}

TEST_P(ScenePackets, WalkLanesIsTheOneRayWalk) {
  const Scene scene = built_in(GetParam());
  const auto expected = camera_paths_one_by_one(scene);
  std::vector<std::vector<PathVertex>> paths(expected.size());
  std::vector<RandomStream> streams;
  std::vector<WalkLane> lanes;
  streams.reserve(paths.size());
  for (std::uint32_t p = 0; p < paths.size(); ++p) {
    RandomStream& rng = streams.emplace_back(stream_of(p));
    const double fx = p % kResolution + rng.uniform(), fy = p / kResolution + rng.uniform();
    const Walk walk = start_camera_path(scene, fx, fy, scene.description().max_length, paths[p]);
    lanes.push_back({walk, &rng, &paths[p]});
  }
  LaneBuffers buffers;
  std::uint64_t rays = 0;
  walk_lanes(scene, lanes, buffers, rays);
  std::uint64_t vertices = 0;
  for (std::size_t p = 0; p < paths.size(); ++p) {
    ASSERT_EQ(paths[p].size(), expected[p].size()) << "pixel " << p;
    for (std::size_t i = 0; i < paths[p].size(); ++i) {
      EXPECT_TRUE(same_bits(paths[p][i], expected[p][i])) << "pixel " << p << " vertex " << i;
    }
    vertices += paths[p].size() - 1;
    // Each walk's stream is left where the one-ray walk leaves it (next-event estimation
    // draws from it next).
    RandomStream alone(stream_of(static_cast<std::uint32_t>(p)));
    std::vector<PathVertex> scratch;
    TraceCounters counters;
    const double fx = p % kResolution + alone.uniform(), fy = p / kResolution + alone.uniform();
    trace_camera_path(scene, fx, fy, alone, scene.description().max_length, scratch, counters);
    EXPECT_EQ(alone.uniform(), streams[p].uniform()) << "pixel " << p;
  }
  EXPECT_GE(rays, vertices);
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, ScenePackets,
                         ::testing::Values("furnace", "cornell", "cornell-glossy", "door-ajar",
                                           "lampshade", "many-lights"),
                         scene_test_name);

}  // namespace
}  // namespace pcbench::scene

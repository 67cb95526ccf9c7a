// Rays in Embree packets and paths in lanes against the one-ray code they stand in for: the same
// hits (triangle and distance, to the bit), the same occlusion answers, and the same subpaths
// (every vertex's every member), on every built-in scene; the Lambertian scatter in lanes
// against walk_scatter on edge cases. What the renderer's images owe to
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
#include "integrands/scenes/scatter_lanes.h"
#include "integrands/scenes/scene.h"
#include "integrands/scenes/turn_trig.h"
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

// The Lambertian scatter in lanes against walk_scatter lane by lane, on inputs a render rarely
// gives: the step's uniform at 0, tiny and next to 1 (a sample in the surface's plane, which is
// invalid), directions to the previous vertex grazing or below the surface, normals along the
// axes (the frame's sign switch at n.z = 0), a camera or a surface vertex before.
TEST(ScatterLanes, LambertianIsWalkScatter) {
  const Scene scene = built_in("cornell");
  std::uint32_t diffuse = 0;
  while (scene.material(diffuse).kind != MaterialKind::kDiffuse) ++diffuse;
  RandomStream rng(stream_of(1));
  const Vec3 normals[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0.6, 0.0, 0.8}};
  const double u1s[] = {0.0, 1e-300, 0.5, 1.0 - 0x1p-53, 0.999};
  std::vector<std::vector<PathVertex>> paths, expected_paths;
  std::vector<Walk> expected_walks;
  std::vector<std::uint8_t> expected_goes;
  std::vector<WalkLane> lanes;
  LaneBuffers buffers;
  for (const Vec3& normal : normals) {
    for (const double u1 : u1s) {
      for (int i = 0; i < 8; ++i) {
        // wo: random, with one grazing (in the plane) and the rest on either side.
        Vec3 wo = normalize(Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5});
        if (i == 0) wo = normalize(wo - normal * dot(wo, normal));
        PathVertex before;
        before.kind = i % 2 == 0 ? VertexKind::kCamera : VertexKind::kSurface;
        before.normal = normalize(Vec3{0.3, 1.0, -0.2});
        PathVertex current;
        current.position = {0.1, 0.2, 0.3};
        current.normal = normal;
        current.to_previous = wo;
        current.triangle = diffuse;
        before.position = current.position + wo * 0.7;
        const Walk walk{.direction = -wo,
                        .direction_pdf = 0.4,
                        .beta = {0.5, 0.25, 1.0},
                        .max_vertices = 8,
                        .previous_delta = i == 3};
        const Hit hit{.distance = 0.7, .triangle = diffuse};
        const double u2 = rng.uniform();
        const CosSin azimuth = cos_sin_of_turn(u2);
        paths.push_back({before, current});
        expected_paths.push_back({before, current});
        Walk alone = walk;
        expected_goes.push_back(
            walk_scatter(scene, hit, u1, azimuth, expected_paths.back(), alone) ? 1 : 0);
        expected_walks.push_back(alone);
        lanes.push_back({walk, nullptr, nullptr});
        const auto k = static_cast<std::uint32_t>(buffers.hits.size());
        buffers.active.push_back(k);
        buffers.scattering.push_back(k);
        buffers.lambertian.push_back(k);
        buffers.hits.push_back(hit);
        buffers.u1.push_back(u1);
        buffers.cos.push_back(azimuth.cos);
        buffers.sin.push_back(azimuth.sin);
      }
    }
  }
  for (std::size_t j = 0; j < lanes.size(); ++j) lanes[j].path = &paths[j];
  buffers.goes.assign(lanes.size(), 2);
  scatter_lambertian(scene, lanes, buffers);
  std::size_t went = 0;
  for (std::size_t j = 0; j < lanes.size(); ++j) {
    ASSERT_EQ(buffers.goes[j], expected_goes[j]) << "lane " << j;
    const Walk& got = lanes[j].walk;
    const Walk& want = expected_walks[j];
    EXPECT_EQ(std::memcmp(&got.beta, &want.beta, sizeof(Rgb)), 0) << "lane " << j;
    EXPECT_TRUE(same_bits(paths[j][0], expected_paths[j][0])) << "lane " << j;
    if (!expected_goes[j]) continue;
    ++went;
    EXPECT_EQ(std::memcmp(&got.direction, &want.direction, sizeof(Vec3)), 0) << "lane " << j;
    EXPECT_EQ(std::memcmp(&got.direction_pdf, &want.direction_pdf, sizeof(double)), 0)
        << "lane " << j;
    EXPECT_EQ(got.previous_delta, want.previous_delta) << "lane " << j;
  }
  // Both outcomes were seen.
  EXPECT_GT(went, lanes.size() / 4);
  EXPECT_LT(went, lanes.size());
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, ScenePackets,
                         ::testing::Values("furnace", "cornell", "cornell-glossy", "door-ajar",
                                           "lampshade", "many-lights"),
                         scene_test_name);

}  // namespace
}  // namespace pcbench::scene

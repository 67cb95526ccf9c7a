// The next-event connections of many prefixes at once (integrands/scenes/next_event_batch.h)
// against connect() and mis_weight() one at a time, on every built-in scene: the same values,
// weights and counters to the bit, under path tracing's counts and others with no strategy but
// emitter hits and next events. The images these make are checked whole by ctest
// estimators.hashes.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "base/rng.h"
#include "integrands/scenes/built_in_scenes.h"
#include "integrands/scenes/connection.h"
#include "integrands/scenes/connection_queue.h"
#include "integrands/scenes/next_event_batch.h"
#include "integrands/scenes/path_vertex.h"
#include "integrands/scenes/scene.h"

namespace pcbench::scene {
namespace {

constexpr std::uint32_t kResolution = 12;

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

class NextEventBatchOn : public ::testing::TestWithParam<std::string> {};

TEST_P(NextEventBatchOn, ValuesWeightsAndCountersAreConnectsAndMisWeights) {
  SceneDescription d = *built_in_scene(GetParam());
  d.width = d.height = kResolution;
  const Scene scene(std::move(d));
  std::vector<std::vector<PathVertex>> paths(kResolution * kResolution);
  TraceCounters setup;
  for (std::uint32_t p = 0; p < paths.size(); ++p) {
    RandomStream rng({.key = 0x7e58, .purpose = StreamPurpose::kCameraPath, .path = p});
    const double fx = p % kResolution + rng.uniform(), fy = p / kResolution + rng.uniform();
    trace_camera_path(scene, fx, fy, rng, scene.description().max_length, paths[p], setup);
  }
  // Every prefix with t >= 2, twice, each with an emitter vertex of its own.
  std::vector<PathVertex> emitters;
  emitters.reserve(2 * paths.size() * (scene.description().max_length + 1));
  std::vector<ConnectionPair> pairs;
  RandomStream rng({.key = 0x7e58, .purpose = StreamPurpose::kEstimatorAux});
  for (int round = 0; round < 2; ++round) {
    for (const auto& path : paths) {
      for (std::uint32_t t = 2; t <= path.size(); ++t) {
        emitters.push_back(sample_emitter_vertex(scene, rng));
        pairs.push_back({std::span(&emitters.back(), 1), std::span(path).first(t)});
      }
    }
  }
  ASSERT_TRUE(all_next_events(pairs));
  std::size_t weighed = 0;
  for (const StrategyCounts counts :
       {StrategyCounts{.emitter_hit = 1.0, .next_event = 1.0, .connection = 0.0},
        StrategyCounts{.emitter_hit = 1.0, .next_event = 4.0, .connection = 0.0},
        StrategyCounts{.emitter_hit = 0.5, .next_event = 2.0, .connection = 0.0},
        StrategyCounts{.emitter_hit = 1.0, .next_event = 0.0, .connection = 0.0}}) {
    ASSERT_TRUE(next_event_only(counts));
    std::vector<Rgb> values(pairs.size());
    std::vector<double> weights(pairs.size());
    TraceCounters batch, reference;
    next_event_values_and_weights(scene, counts, pairs, values, weights, batch);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const Rgb want = connect(scene, pairs[i].light, pairs[i].camera, counts,
                               {.visibility = false, .weighted = false}, reference);
      ASSERT_TRUE(same_bits(values[i].r, want.r) && same_bits(values[i].g, want.g) &&
                  same_bits(values[i].b, want.b))
          << "pair " << i << " t " << pairs[i].camera.size();
      if (want.is_black()) continue;
      const double w = mis_weight(scene, pairs[i].light, pairs[i].camera, counts);
      ASSERT_TRUE(same_bits(weights[i], w)) << "pair " << i << ": " << weights[i] << " " << w;
      ++weighed;
    }
    EXPECT_EQ(batch.connections, reference.connections);
    EXPECT_EQ(batch.skipped_zero, reference.skipped_zero);
  }
  EXPECT_GT(weighed, 100u);  // the comparison saw weights, not only zeros
}

TEST(NextEventBatch, AppliesOnlyToNextEventsUnderCountsWithNothingElse) {
  EXPECT_TRUE(next_event_only({.emitter_hit = 1.0, .next_event = 1.0, .connection = 0.0}));
  EXPECT_FALSE(next_event_only({}));  // BDPT's: connections
  EXPECT_FALSE(next_event_only({.connection = 0.0, .light_tracing = 16384.0}));
  std::vector<PathVertex> camera(3), light(2);
  light[0].kind = VertexKind::kEmitter;
  EXPECT_TRUE(all_next_events(std::vector<ConnectionPair>{
      {std::span(light).first(1), std::span(camera)}}));
  EXPECT_FALSE(all_next_events(std::vector<ConnectionPair>{
      {std::span(light), std::span(camera)}}));  // s = 2
  EXPECT_FALSE(all_next_events(std::vector<ConnectionPair>{
      {std::span(light).first(1), std::span(camera).first(1)}}));  // t = 1
  light[0].kind = VertexKind::kSurface;
  EXPECT_FALSE(all_next_events(std::vector<ConnectionPair>{
      {std::span(light).first(1), std::span(camera)}}));
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, NextEventBatchOn, ::testing::ValuesIn(built_in_scene_names()),
                         [](const auto& test) {
                           std::string name = test.param;
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace pcbench::scene
